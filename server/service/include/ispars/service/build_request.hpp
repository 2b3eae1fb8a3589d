#pragma once
// A build request and the checks it passes before it reaches a session: its sample count against
// this daemon's limits, and its choices and overrides against the scene, giving the recipe the
// build will run; and the check a stored roadmap passes before it is served. Pure functions (no
// session, no store): each refusal is an InputError naming the request's field, unit-tested
// without a daemon (tests/server/test_build_request.cpp).

#include <cstdint>
#include <string>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/build_request.hpp"

namespace ispars::service {

/// The build request that makes `recipe`'s roadmap to `samples` samples: its method, variant and
/// seed, with its deltas, stretch and p_accept as overrides (request_build's inverse; a value of 0,
/// unknown to the sender, is left to the scene), and its generation.
[[nodiscard]] BuildRequest rebuild_request(const RoadmapRecipe& recipe, std::uint64_t samples);

/// Limits a session enforces on requests.
struct SessionLimits {
  std::uint64_t max_samples = 50'000'000;  ///< Per build or extend request.
  std::size_t compact_every = 64;          ///< Journal commits between store compactions.
  unsigned build_threads = 1;              ///< Threads per build (any count: the same roadmap).
};

/// A build's or extend's sample count: at least 1, at most limits.max_samples (InputError, field
/// "samples").
void check_samples(std::uint64_t samples, const SessionLimits& limits);

/// The recipe `request` asks for on scene `name` (its `scene`): make_recipe's, with the sample
/// count checked against this daemon's limits too. Its generation, fingerprint and builder version
/// are left to the session, which sets them when the build is queued.
[[nodiscard]] RoadmapRecipe requested_recipe(const std::string& name, const planning::Scene& scene,
                                             const BuildRequest& request, const SessionLimits& limits);

/// Why a stored roadmap of `stored` must not be served for scene `name`, whose file's fingerprint
/// is now `fingerprint`: another version of the scene, or of the builders. Empty when it may.
[[nodiscard]] std::string stale_store_reason(const std::string& name, const RoadmapRecipe& stored,
                                             const std::string& fingerprint);

}  // namespace ispars::service
