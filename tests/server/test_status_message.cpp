// The daemon's status message: the recipe and the counts of a session, and the state's name.

#include <gtest/gtest.h>

#include "ispars/wire/convert.hpp"
#include "status_message.hpp"

namespace ispars::server {
namespace {

TEST(StatusMessage, StatusCarriesTheRecipeAndCounts) {
  SessionStatus s;
  s.scene = "tower";
  s.state = SessionState::building;
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

}  // namespace
}  // namespace ispars::server
