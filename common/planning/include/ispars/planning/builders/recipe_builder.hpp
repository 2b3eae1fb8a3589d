#pragma once
// From a build request to its recipe and its builder, in one place for every caller: the
// service's build requests, the Python package's offline builds and the lab. The same request
// give the same recipe, the same checks (each refusal an InputError naming its field), and the
// same roadmap, byte for byte.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/build_request.hpp"

namespace ispars::planning {

/// The recipe `request` asks for on scene `name` (`scene`): the one place a build's choices are
/// checked, for the daemon, Python and the lab alike. Its sample count in kSamples' range; a
/// variant only for a method with variants; each override in its declared range, then against
/// the scene's scale; the slack only where it is read. The scene's deltas and stretch, with the
/// overrides applied. Throws InputError (file `file`, field "samples", "variant" or
/// "overrides.NAME") naming the first bad one. Generation, fingerprint and builder version are
/// left at their defaults.
[[nodiscard]] RoadmapRecipe make_recipe(const std::string& name, const Scene& scene, const BuildRequest& request,
                                        std::string_view file);

/// `scene` with `recipe`'s deltas and stretch: the scene its roadmap is built in.
[[nodiscard]] Scene recipe_scene(const Scene& scene, const RoadmapRecipe& recipe, std::string_view file);

/// The builder settings of `recipe` on `threads` threads (any count gives the same roadmap).
[[nodiscard]] BuildOptions recipe_build_options(const RoadmapRecipe& recipe, unsigned threads);

/// What `recipe`'s method promises, checked exactly on its roadmaps after `samples` samples, in
/// `scene` (recipe_scene's): every vertex and edge, and Invariant 1 where the method promises it
/// (over the dense pair for spars and ispars; for ispars2, over its stream's samples drawn again).
[[nodiscard]] VerificationReport verify_recipe_roadmaps(const Scene& scene, const RoadmapRecipe& recipe,
                                                        std::uint64_t samples, const Roadmap& roadmap,
                                                        const Roadmap* dense, std::span<const VertexId> dense_ids,
                                                        const VerifyKeepGoing& keep_going = {});

/// Whether `method` promises Invariant 1: Inspection-SPARS does (ispars, ispars2); SPARS and the
/// others do not.
[[nodiscard]] bool promises_invariant(BuildMethod method);

/// The problems in `report` that `method` promises to avoid: every invalid vertex or edge, wrong
/// cost and sparse vertex not dense, and the Invariant 1 violations where it promises them.
/// Invariant 1 on fresh samples (invariant_samples > 0) estimates what a roadmap misses between
/// the samples it drew, not a broken promise: reported, not counted.
[[nodiscard]] std::uint64_t broken_promises(const VerificationReport& report, bool invariant_promised);

}  // namespace ispars::planning
