#include "ispars/planning/builders/recipe_builder.hpp"

#include <fmt/format.h>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::planning {
namespace {

// Parameters far off the scene's scale make a single neighbourhood query scan millions of grid
// cells, and a build that can never be cancelled: refused.
void check_override_scale(const Scene& scene, const RoadmapRecipe& recipe, const std::string& file) {
  const double diagonal = (scene.config().bounds.max - scene.config().bounds.min).norm();
  if (recipe.dense_delta < diagonal * 1e-4) {
    throw params::InputError(file, "overrides.dense_delta",
                             fmt::format("{} is too small for this scene (at least {:.4g}, 1e-4 of its diagonal)",
                                         recipe.dense_delta, diagonal * 1e-4));
  }
  if (recipe.sparse_delta > diagonal) {
    throw params::InputError(
        file, "overrides.sparse_delta",
        fmt::format("{} is larger than the scene's diagonal ({:.4g})", recipe.sparse_delta, diagonal));
  }
  if (recipe.sparse_delta > 50 * recipe.dense_delta) {
    throw params::InputError(
        file, "overrides.sparse_delta",
        fmt::format("must be at most 50 times dense_delta (got {} and {})", recipe.sparse_delta, recipe.dense_delta));
  }
}

}  // namespace

RoadmapRecipe make_recipe(const std::string& name, const Scene& scene, const BuildRequest& request,
                          std::string_view file) {
  const std::string source(file);
  if (std::string p = params::problem(kSamples, request.samples); !p.empty())
    throw params::InputError(source, "samples", p);
  if (request.variant && !has_variants(request.method)) {
    throw params::InputError(source, "variant",
                             fmt::format("'{}' given, but {} has no rule-set variants (spars and ispars have)",
                                         to_string(*request.variant), to_string(request.method)));
  }
  params::check(request.overrides, file, "overrides.");
  RoadmapRecipe recipe;
  recipe.scene = name;
  recipe.method = request.method;
  recipe.variant = request.variant.value_or(SparsVariant::stretch);
  recipe.seed = request.seed;
  recipe.dense_delta = scene.config().dense_delta;
  recipe.sparse_delta = scene.config().sparse_delta;
  recipe.stretch = scene.config().stretch;
  params::overlay(request.overrides, recipe);
  check_stretch_slack(recipe, file);
  (void)recipe_scene(scene, recipe, file);  // throws InputError naming the bad one
  if (request.overrides.any()) check_override_scale(scene, recipe, source);
  return recipe;
}

Scene recipe_scene(const Scene& scene, const RoadmapRecipe& recipe, std::string_view file) {
  return scene.with_roadmap_parameters(recipe.dense_delta, recipe.sparse_delta, recipe.stretch, std::string(file));
}

BuildOptions recipe_build_options(const RoadmapRecipe& recipe, unsigned threads) {
  BuildOptions options;
  options.seed = recipe.seed;
  options.threads = threads;
  options.p_accept = recipe.p_accept;
  options.stretch_slack = recipe.stretch_slack;
  options.stretch_slack_after = recipe.stretch_slack_after;
  options.variant = recipe.variant;
  return options;
}

VerificationReport verify_recipe_roadmaps(const Scene& scene, const RoadmapRecipe& recipe, std::uint64_t samples,
                                          const Roadmap& roadmap, const Roadmap* dense,
                                          std::span<const VertexId> dense_ids, const VerifyKeepGoing& keep_going) {
  if (dense) return verify_sparse_pair(scene, roadmap, *dense, dense_ids, keep_going);
  VerificationReport report = verify_roadmap(scene, roadmap, keep_going);
  if (recipe.method == BuildMethod::ispars2) {
    // No dense graph keeps the samples drawn: they are drawn again from the seed, and checked
    // exactly as ispars's dense vertices are (Claim 1's promise, tasks' POIs included).
    const VerificationReport drawn = verify_drawn_samples(scene, roadmap, recipe.seed, samples, keep_going);
    report.invariant_violations = drawn.invariant_violations;
    report.invariant_vertices = drawn.invariant_vertices;
    report.invariant_drawn = drawn.invariant_drawn;
  }
  return report;
}

bool promises_invariant(BuildMethod method) { return method == BuildMethod::ispars || method == BuildMethod::ispars2; }

std::uint64_t broken_promises(const VerificationReport& report, bool invariant_promised) {
  const bool counted = invariant_promised && report.invariant_samples == 0;
  return report.invalid_vertices + report.invalid_edges + report.wrong_costs + report.sparse_not_dense +
         (counted ? report.invariant_violations : 0);
}

}  // namespace ispars::planning
