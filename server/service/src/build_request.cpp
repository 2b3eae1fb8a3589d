#include "ispars/service/build_request.hpp"

#include <fmt/format.h>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "request_input.hpp"

namespace ispars::service {

BuildRequest rebuild_request(const RoadmapRecipe& recipe, std::uint64_t samples) {
  BuildRequest request;
  request.method = recipe.method;
  request.seed = recipe.seed;
  request.samples = samples;
  request.generation = recipe.generation;
  request.variant = has_variants(recipe.method) ? std::optional(recipe.variant) : std::nullopt;
  // Every parameter as an override (a value of 0, unknown to the sender, is left to the scene).
  params::for_matching(recipe, request.overrides, [](const auto&, const auto& value, auto& override) {
    if (value > 0) override = value;
  });
  return request;
}

void check_samples(std::uint64_t samples, const SessionLimits& limits) {
  if (samples == 0) throw params::InputError(kRequest, "samples", "must be at least 1");
  if (samples > limits.max_samples) {
    throw params::InputError(
        kRequest, "samples",
        fmt::format("{} is more than this daemon allows per request ({})", samples, limits.max_samples));
  }
}

RoadmapRecipe requested_recipe(const std::string& name, const planning::Scene& scene, const BuildRequest& request,
                               const SessionLimits& limits) {
  check_samples(request.samples, limits);
  return make_recipe(name, scene, request, kRequest);
}

std::string stale_store_reason(const std::string& name, const RoadmapRecipe& stored, const std::string& fingerprint) {
  if (!stored.scene_fingerprint.empty() && stored.scene_fingerprint != fingerprint) {
    return fmt::format(
        "the stored roadmap of scene '{}' was built on another version of the scene (its mesh, POIs "
        "or parameters changed: fingerprint {} stored, {} now); it is left untouched",
        name, stored.scene_fingerprint, fingerprint);
  }
  if (stored.builder_version != 0 && stored.builder_version != kBuilderVersion) {
    return fmt::format(
        "the stored roadmap of scene '{}' was made by builder version {}, and this ispars has "
        "version {}; it is left untouched",
        name, stored.builder_version, kBuilderVersion);
  }
  return {};
}

}  // namespace ispars::service
