#include "ispars/service/build_request.hpp"

#include <fmt/format.h>

#include "ispars/input_error.hpp"
#include "request_input.hpp"

namespace ispars {
namespace {

// Parameters far off the scene's scale make a single neighbourhood query scan millions of grid
// cells, and a build that can never be cancelled: refused.
void check_override_scale(const Scene& scene, const RoadmapRecipe& recipe) {
  const double diagonal = (scene.config().bounds.max - scene.config().bounds.min).norm();
  if (recipe.dense_delta < diagonal * 1e-4) {
    throw InputError(kRequest, "overrides.dense_delta",
                     fmt::format("{} is too small for this scene (at least {:.4g}, 1e-4 of its diagonal)",
                                 recipe.dense_delta, diagonal * 1e-4));
  }
  if (recipe.sparse_delta > diagonal) {
    throw InputError(kRequest, "overrides.sparse_delta",
                     fmt::format("{} is larger than the scene's diagonal ({:.4g})", recipe.sparse_delta, diagonal));
  }
  if (recipe.sparse_delta > 50 * recipe.dense_delta) {
    throw InputError(kRequest, "overrides.sparse_delta",
                     fmt::format("must be at most 50 times dense_delta (got {} and {})", recipe.sparse_delta,
                                 recipe.dense_delta));
  }
}

}  // namespace

BuildRequest rebuild_request(const RoadmapRecipe& recipe, std::uint64_t samples) {
  BuildRequest request;
  request.method = recipe.method;
  request.variant = recipe.variant;
  request.seed = recipe.seed;
  request.samples = samples;
  request.generation = recipe.generation;
  for (const RecipeParameter& p : recipe_overrides()) {
    if (p.get(recipe) > 0.0) request.overrides.emplace(std::string(p.name), p.get(recipe));
  }
  return request;
}

void check_samples(std::uint64_t samples, const SessionLimits& limits) {
  if (samples == 0) throw InputError(kRequest, "samples", "must be at least 1");
  if (samples > limits.max_samples) {
    throw InputError(kRequest, "samples",
                     fmt::format("{} is more than this daemon allows per request ({})", samples, limits.max_samples));
  }
}

RoadmapRecipe requested_recipe(const std::string& name, const Scene& scene, const BuildRequest& request,
                               const SessionLimits& limits) {
  check_samples(request.samples, limits);
  RoadmapRecipe recipe;
  recipe.scene = name;
  recipe.method = request.method;
  recipe.variant = request.variant;
  recipe.seed = request.seed;
  recipe.dense_delta = scene.config().dense_delta;
  recipe.sparse_delta = scene.config().sparse_delta;
  recipe.stretch = scene.config().stretch;
  for (const auto& [key, value] : request.overrides) set_recipe_override(recipe, key, value, kRequest);
  check_stretch_slack(recipe, kRequest);
  (void)scene.with_roadmap_parameters(recipe.dense_delta, recipe.sparse_delta, recipe.stretch,
                                      kRequest);  // throws InputError naming the bad one
  if (!request.overrides.empty()) check_override_scale(scene, recipe);
  return recipe;
}

std::string stale_store_reason(const std::string& name, const RoadmapRecipe& stored, const std::string& fingerprint) {
  if (!stored.scene_fingerprint.empty() && stored.scene_fingerprint != fingerprint) {
    return fmt::format("the stored roadmap of scene '{}' was built on another version of the scene (its mesh, POIs "
                       "or parameters changed: fingerprint {} stored, {} now); it is left untouched",
                       name, stored.scene_fingerprint, fingerprint);
  }
  if (stored.builder_version != 0 && stored.builder_version != kBuilderVersion) {
    return fmt::format("the stored roadmap of scene '{}' was made by builder version {}, and this ispars has "
                       "version {}; it is left untouched",
                       name, stored.builder_version, kBuilderVersion);
  }
  return {};
}

}  // namespace ispars
