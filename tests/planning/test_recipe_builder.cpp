// From a build's choices to its recipe and builder (builders/recipe_builder.hpp), as the daemon
// and the Python package share it: names parsed and refused by field under the caller's file,
// the recipe's builder equal to one made by hand, and the promises verification counts.

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

const Scene& tower() { return test::shared_scene("demo_tank_tower"); }

std::string refusal_of(std::string_view method, std::string_view variant) {
  try {
    BuildRequest request;
    request.samples = 100;
    set_method(request, method, variant, "call");
    (void)make_recipe("t", tower(), request, "call");
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "accepted";
}

BuildRequest request(std::uint64_t samples = 100) {
  BuildRequest r;
  r.samples = samples;
  return r;
}

TEST(RecipeBuilder, ChoicesAreParsedAndRefusedByFieldUnderTheCallersFile) {
  EXPECT_EQ(refusal_of("spars", "alg1"), "accepted");
  EXPECT_EQ(make_recipe("t", tower(), request_of("ispars2", 5), "call").variant, SparsVariant::stretch);
  EXPECT_EQ(refusal_of("ispars2", "alg1"),
            "call: variant: 'alg1' given, but ispars2 has no rule-set variants (spars and ispars have)");
  EXPECT_EQ(refusal_of("prm", ""), "call: method: 'prm' is not one of dense, spars, ispars, irisc, ispars2");
  EXPECT_EQ(refusal_of("ispars", "loose"), "call: variant: 'loose' is not one of stretch, alg1");
  EXPECT_EQ(refusal_of("dense", "alg1"),
            "call: variant: 'alg1' given, but dense has no rule-set variants (spars and ispars have)");
}

TEST(RecipeBuilder, TheSampleCountIsCheckedAgainstItsDeclaredRange) {
  EXPECT_THROW((void)make_recipe("t", tower(), request(0), "call"), params::InputError);
  EXPECT_THROW((void)make_recipe("t", tower(), request(kSamples.max + 1), "call"), params::InputError);
  EXPECT_NO_THROW((void)make_recipe("t", tower(), request(kSamples.max), "call"));
}

TEST(RecipeBuilder, OverridesAreCheckedByRangeThenByTheScenesScale) {
  BuildRequest c = request();
  c.overrides.p_accept = 1.5;
  EXPECT_THROW((void)make_recipe("t", tower(), c, "call"), params::InputError);
  c.overrides = {};
  c.overrides.sparse_delta = 1e5;
  try {
    (void)make_recipe("t", tower(), c, "call");
    FAIL() << "a Delta larger than the scene was accepted";
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.file(), "call");
    EXPECT_EQ(e.field(), "overrides.sparse_delta");
  }
  c.overrides = {};
  c.overrides.stretch = 2.5;
  const RoadmapRecipe r = make_recipe("t", tower(), c, "call");
  EXPECT_EQ(r.stretch, 2.5);
  EXPECT_EQ(r.dense_delta, tower().config().dense_delta);
  EXPECT_EQ(recipe_scene(tower(), r, "call").config().stretch, 2.5);
}

TEST(RecipeBuilder, TheRecipesBuilderIsTheOneMadeByHand) {
  BuildRequest c = request();
  c.method = BuildMethod::ispars;
  c.seed = 7;
  c.overrides.p_accept = 0.3;
  c.overrides.stretch_slack = 0.1;
  const RoadmapRecipe r = make_recipe("t", tower(), c, "call");
  const Scene scene = recipe_scene(tower(), r, "call");
  const BuildOptions options = recipe_build_options(r, 3);
  EXPECT_EQ(options.seed, 7u);
  EXPECT_EQ(options.threads, 3u);
  EXPECT_EQ(options.p_accept, 0.3);
  EXPECT_EQ(options.stretch_slack, 0.1);
  BuildOptions by_hand;
  by_hand.seed = 7;
  by_hand.p_accept = 0.3;
  by_hand.stretch_slack = 0.1;
  const auto a = make_roadmap_builder(BuildMethod::ispars, scene, options);
  const auto b = make_roadmap_builder(BuildMethod::ispars, scene, by_hand);
  a->extend(800);
  b->extend(800);
  EXPECT_EQ(roadmap_digest(a->roadmap()), roadmap_digest(b->roadmap()));
  const VerificationReport report =
      verify_recipe_roadmaps(scene, r, a->samples(), a->roadmap(), a->dense(), a->dense_ids());
  EXPECT_EQ(broken_promises(report, promises_invariant(r.method)), 0u);
}

TEST(RecipeBuilder, BrokenPromisesCountInvariantViolationsOnlyWherePromisedAndNotOnFreshSamples) {
  VerificationReport r;
  r.invalid_edges = 2;
  r.invariant_violations = 5;
  EXPECT_EQ(broken_promises(r, true), 7u);
  EXPECT_EQ(broken_promises(r, false), 2u);
  r.invariant_samples = 100;  // an estimate on fresh samples, not a promise
  EXPECT_EQ(broken_promises(r, true), 2u);
  EXPECT_TRUE(promises_invariant(BuildMethod::ispars));
  EXPECT_TRUE(promises_invariant(BuildMethod::ispars2));
  EXPECT_FALSE(promises_invariant(BuildMethod::spars));
  EXPECT_FALSE(promises_invariant(BuildMethod::dense));
}

}  // namespace
}  // namespace ispars::planning
