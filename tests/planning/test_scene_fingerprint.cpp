// The scene fingerprint a stored roadmap records: equal for the same scene, different when the
// mesh, the POIs or a parameter changes.

#include <gtest/gtest.h>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/scene/scene_fingerprint.hpp"
#include "ispars/scene_files/scene_config.hpp"

namespace ispars::planning {
namespace {

Scene procedural(int seed) {
  return Scene::build(scene_files::parse_scene_config_text(
      "procedural: {kind: tank_tower, seed: " + std::to_string(seed) + "}", ".", "test.yaml"));
}

TEST(SceneFingerprint, EqualForTheSameSceneAndDifferentForAnyChange) {
  const Scene a = procedural(1);
  const std::string fa = scene_fingerprint(a);
  EXPECT_EQ(fa.size(), 16u);
  EXPECT_EQ(scene_fingerprint(procedural(1)), fa) << "built twice, the same scene";
  EXPECT_NE(scene_fingerprint(procedural(2)), fa) << "another mesh";
  const scene_files::SceneConfig& c = a.config();
  EXPECT_NE(scene_fingerprint(a.with_roadmap_parameters(c.dense_delta * 1.01, c.sparse_delta, c.stretch, "t")), fa);
  EXPECT_NE(scene_fingerprint(a.with_roadmap_parameters(c.dense_delta, c.sparse_delta * 1.01, c.stretch, "t")), fa);
  EXPECT_NE(scene_fingerprint(a.with_roadmap_parameters(c.dense_delta, c.sparse_delta, c.stretch * 1.01, "t")), fa);
  EXPECT_EQ(scene_fingerprint(a.with_roadmap_parameters(c.dense_delta, c.sparse_delta, c.stretch, "t")), fa);
}

}  // namespace
}  // namespace ispars::planning
