// The daemon's status message: the recipe and the counts of a session, and the state's name.

#include <gtest/gtest.h>

#include "ispars/server/status_message.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

TEST(StatusMessage, StatusCarriesTheRecipeAndCounts) {
  service::SessionStatus s;
  s.scene = "tower";
  s.state = service::SessionState::building;
  s.recipe = RoadmapRecipe{"tower", BuildMethod::spars, 4, 0.2, SparsVariant::alg1, 1.0, 2.0, 1.1, 77, "", 0};
  s.samples_done = 10;
  s.samples_target = 20;
  s.vertices = 5;
  const msg::SceneStatus m = to_message(s, "d1", 77);
  EXPECT_EQ(m.state(), msg::SCENE_BUILDING);
  EXPECT_EQ(m.method(), "spars");
  EXPECT_EQ(m.variant(), "alg1");
  EXPECT_EQ(m.seed(), 4u);
  EXPECT_EQ(m.sparse_delta(), 2.0);
  EXPECT_EQ(m.generation(), 77u);
  EXPECT_EQ(m.vertices(), 5u);
  EXPECT_EQ(wire::to_string(m.state()), "building");
  EXPECT_EQ(wire::to_string(msg::SCENE_UNLOADED), "unloaded");
}

// A daemon taking a scene over reads the recipe back from the last status: the same roadmap,
// and the build request that makes it.
TEST(StatusMessage, TheRecipeReadsBackAsTheSameRoadmapAndItsRebuildRequest) {
  service::SessionStatus s;
  s.scene = "tower";
  s.state = service::SessionState::idle;
  s.recipe =
      RoadmapRecipe{"tower", BuildMethod::ispars, 9, 0.3, SparsVariant::alg1, 1.25, 2.5, 1.5, 77, "fp", 1, 0.5, 2000};
  const msg::SceneStatus m = to_message(s, "d1", 77);
  const auto back = recipe_of(m);
  ASSERT_TRUE(back.has_value());
  EXPECT_TRUE(same_roadmap(*back, *s.recipe));
  EXPECT_EQ(back->generation, 77u);
  RoadmapRecipe other = *s.recipe;
  other.p_accept = 0.4;
  EXPECT_FALSE(same_roadmap(*back, other));
  other = *s.recipe;
  other.stretch_slack = 0.25;
  EXPECT_FALSE(same_roadmap(*back, other)) << "a takeover must rebuild with the same slack";
  other = *s.recipe;
  other.stretch_slack_after = 0;
  EXPECT_FALSE(same_roadmap(*back, other)) << "and from the same sample on";
  other = *s.recipe;
  other.variant = SparsVariant::stretch;
  EXPECT_FALSE(same_roadmap(*back, other));
  other.method = BuildMethod::dense;  // a method without variants: the variant does not count
  RoadmapRecipe dense = *back;
  dense.method = BuildMethod::dense;
  EXPECT_TRUE(same_roadmap(dense, other));

  const BuildRequest request = service::rebuild_request(*back, 4000);
  EXPECT_EQ(request.method, BuildMethod::ispars);
  EXPECT_EQ(request.variant, SparsVariant::alg1);
  EXPECT_EQ(request.seed, 9u);
  EXPECT_EQ(request.samples, 4000u);
  EXPECT_FALSE(request.replace);
  const RecipeOverrides overrides{1.25, 2.5, 1.5, 0.5, 2000, 0.3};
  EXPECT_EQ(request.overrides, overrides);

  msg::SceneStatus unknown = m;
  unknown.method("rrt");
  EXPECT_FALSE(recipe_of(unknown).has_value());
  unknown = m;
  unknown.variant("nonsense");
  EXPECT_FALSE(recipe_of(unknown).has_value());
  EXPECT_FALSE(recipe_of(msg::SceneStatus{}).has_value()) << "a status without a roadmap names no method";
}

}  // namespace
}  // namespace ispars::server
