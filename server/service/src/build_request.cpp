#include "ispars/service/build_request.hpp"

#include <fmt/format.h>

#include "ispars/builders/recipe_builder.hpp"
#include "ispars/input_error.hpp"
#include "request_input.hpp"

namespace ispars {

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
  RecipeChoices choices;
  choices.method = request.method;
  choices.variant = request.variant;
  choices.seed = request.seed;
  choices.overrides = request.overrides;
  return recipe_for(name, scene, choices, kRequest);
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
