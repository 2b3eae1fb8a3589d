// A build request's checks, without a session: the recipe it asks for on a scene, each refusal
// named by field, rebuild_request as its inverse, and when a stored roadmap is stale.

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/build_request.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

const planning::Scene& tower() { return test::shared_scene("demo_tank_tower"); }

BuildRequest asking(std::uint64_t samples) {
  BuildRequest r;
  r.method = BuildMethod::ispars;
  r.samples = samples;
  r.seed = 4;
  return r;
}

std::string refusal(const BuildRequest& request, const SessionLimits& limits = {}) {
  try {
    (void)requested_recipe("tower", tower(), request, limits);
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(BuildRequest, TheRecipeTakesTheScenesParametersUnlessOverridden) {
  const scene_files::SceneConfig& c = tower().config();
  const RoadmapRecipe plain = requested_recipe("tower", tower(), asking(100), {});
  EXPECT_EQ(plain.scene, "tower");
  EXPECT_EQ(plain.method, BuildMethod::ispars);
  EXPECT_EQ(plain.seed, 4u);
  EXPECT_EQ(plain.dense_delta, c.dense_delta);
  EXPECT_EQ(plain.sparse_delta, c.sparse_delta);
  EXPECT_EQ(plain.stretch, c.stretch);
  EXPECT_EQ(plain.generation, 0u) << "the session sets it when the build is queued";
  BuildRequest r = asking(100);
  r.overrides.sparse_delta = c.sparse_delta * 1.5;
  r.overrides.stretch = 2.5;
  const RoadmapRecipe overridden = requested_recipe("tower", tower(), r, {});
  EXPECT_EQ(overridden.sparse_delta, c.sparse_delta * 1.5);
  EXPECT_EQ(overridden.stretch, 2.5);
  EXPECT_EQ(overridden.dense_delta, c.dense_delta);
}

TEST(BuildRequest, SamplesAreAtLeastOneAndAtMostTheLimit) {
  SessionLimits limits;
  limits.max_samples = 1000;
  EXPECT_NE(refusal(asking(0), limits).find("request: samples: must be at least 1"), std::string::npos);
  EXPECT_EQ(refusal(asking(1000), limits), "accepted");
  EXPECT_NE(refusal(asking(1001), limits).find("samples: 1001 is more than this daemon allows per request (1000)"),
            std::string::npos);
  EXPECT_THROW(check_samples(0, limits), params::InputError);
  EXPECT_NO_THROW(check_samples(1, limits));
}

TEST(BuildRequest, OverridesOffTheScenesScaleAreRefusedByName) {
  const scene_files::SceneConfig& c = tower().config();
  BuildRequest r = asking(100);
  r.overrides.dense_delta = 1e-6;
  EXPECT_NE(refusal(r).find("overrides.dense_delta: 1e-06 is too small for this scene"), std::string::npos)
      << refusal(r);
  const double diagonal = (c.bounds.max - c.bounds.min).norm();
  const double dense = diagonal / 100;  // so that 60 times it stays within the diagonal
  r.overrides.dense_delta = dense;
  r.overrides.sparse_delta = dense * 60;
  EXPECT_NE(refusal(r).find("overrides.sparse_delta: must be at most 50 times dense_delta"), std::string::npos)
      << refusal(r);
  r.overrides.sparse_delta = dense * 50;
  EXPECT_EQ(refusal(r), "accepted") << "50 times is the bound, not past it";
}

TEST(BuildRequest, ARebuildRequestAsksForTheSameRecipe) {
  BuildRequest r = asking(700);
  r.variant = SparsVariant::alg1;
  r.overrides.sparse_delta = tower().config().sparse_delta * 1.25;
  RoadmapRecipe recipe = requested_recipe("tower", tower(), r, {});
  recipe.generation = 42;
  const BuildRequest again = rebuild_request(recipe, 900);
  EXPECT_EQ(again.samples, 900u);
  EXPECT_EQ(again.generation, 42u);
  EXPECT_EQ(again.variant, SparsVariant::alg1);
  const RoadmapRecipe same = requested_recipe("tower", tower(), again, {});
  EXPECT_EQ(same.method, recipe.method);
  EXPECT_EQ(same.seed, recipe.seed);
  EXPECT_EQ(same.dense_delta, recipe.dense_delta);
  EXPECT_EQ(same.sparse_delta, recipe.sparse_delta);
  EXPECT_EQ(same.stretch, recipe.stretch);
}

TEST(BuildRequest, AStoredRoadmapOfAnotherSceneVersionOrBuilderIsStale) {
  RoadmapRecipe stored = requested_recipe("tower", tower(), asking(100), {});
  stored.scene_fingerprint += "abc";  // appended: GCC 12 warns falsely on assigning a short literal
  stored.builder_version = kBuilderVersion;
  EXPECT_EQ(stale_store_reason("tower", stored, "abc"), "");
  EXPECT_NE(stale_store_reason("tower", stored, "abd").find("built on another version of the scene"),
            std::string::npos);
  stored.builder_version = kBuilderVersion + 1;
  EXPECT_NE(stale_store_reason("tower", stored, "abc").find("made by builder version"), std::string::npos);
  stored.builder_version = 0;  // stores that predate the builder version: unchecked
  stored.scene_fingerprint.clear();
  EXPECT_EQ(stale_store_reason("tower", stored, "abc"), "");
}

}  // namespace
}  // namespace ispars::service
