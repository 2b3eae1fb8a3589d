#pragma once
// From a build's choices to its recipe and its builder, in one place for every caller: the
// service's build requests, the Python package's offline builds and the lab. The same choices
// give the same recipe, the same checks (each refusal an InputError naming its field), and the
// same roadmap, byte for byte.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>

#include "ispars/builders/roadmap_builder.hpp"
#include "ispars/builders/roadmap_verifier.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/scene/scene.hpp"

namespace ispars {

/// What a caller chooses of a recipe: the method, the rule set, the seed and the scene parameters
/// it overrides, by name (recipe_overrides() in build_recipe.hpp).
struct RecipeChoices {
  BuildMethod method = BuildMethod::ispars;
  SparsVariant variant = SparsVariant::stretch;
  std::uint64_t seed = 1;
  std::map<std::string, double> overrides;
};

/// The method and variant named by text, as a request or a Python call names them: `method` one
/// of build_method_names(); `variant` empty (stretch) or one of spars_variant_names(), and only
/// for a method with variants. Throws InputError (file `file`, field "method" or "variant").
[[nodiscard]] RecipeChoices parse_recipe_choices(std::string_view method, std::string_view variant,
                                                 std::string_view file);

/// The recipe `choices` make on scene `name` (`scene`): the scene's deltas and stretch, with the
/// overrides checked (each by its declared range, then against the scene's scale) and applied.
/// Throws InputError (file `file`, field "overrides.NAME") naming the first bad one. Generation,
/// fingerprint and builder version are left at their defaults.
[[nodiscard]] RoadmapRecipe recipe_for(const std::string& name, const Scene& scene, const RecipeChoices& choices,
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

}  // namespace ispars
