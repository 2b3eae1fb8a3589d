// DenseBuilder (the paper's Dense baseline, the delta-PRM alone): the root first, every valid
// sample of the seeded stream inserted with its POIs and its delta-edges, invalid ones dropped
// but counted, and a resumed builder that starts from the given roadmap. (Determinism, resuming
// byte for byte and thread counts are checked for every method in test_roadmap_builder.)

#include <gtest/gtest.h>

#include "ispars/planning/builders/delta_prm.hpp"
#include "ispars/planning/builders/dense_builder.hpp"
#include "ispars/scene_files/random.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// open_scene with its wall, sampled in a small box around it (|x|, |y|, |z| <= 3), so that
// samples are dense enough for edges and some fall within the robot radius of the wall.
Scene small_box_scene() {
  const Scene base = test::open_scene(1.0, 2.0, true);
  scene_files::SceneConfig config = base.config();
  config.bounds = {Vec3(-3, -3, -3), Vec3(3, 3, 3)};
  return Scene::build(config, base.mesh());
}

TEST(DenseBuilder, StartsWithTheRootAndWhatItSees) {
  const Scene scene = test::open_scene(1.0, 2.0);
  const DenseBuilder b(scene, BuildOptions{});
  ASSERT_EQ(b.roadmap().vertex_count(), 1u);
  EXPECT_EQ(b.roadmap().position(0), scene.config().root);
  EXPECT_EQ(b.roadmap().visibility_table().ids(0), scene.visibility().visible_pois(scene.config().root));
  EXPECT_EQ(b.samples(), 0u);
  EXPECT_EQ(b.dense(), nullptr);
  EXPECT_TRUE(b.dense_ids().empty());
}

TEST(DenseBuilder, StepInsertsAValidSampleWithItsDeltaEdgesAndDropsAnInvalidOne) {
  const Scene scene = test::open_scene(1.0, 2.0, true);  // wall at x = 2.5, robot radius 0.1
  DenseBuilder b(scene, BuildOptions{});
  b.step(Vec3(1, 0, 0));     // exactly delta from the root
  b.step(Vec3(2.45, 0, 0));  // within the robot radius of the wall: dropped
  b.step(Vec3(2.0, 0, 0));
  b.step(Vec3(2.9, 0, 0));  // 0.9 from (2, 0, 0), the wall between
  const Roadmap& g = b.roadmap();
  ASSERT_EQ(g.vertex_count(), 4u);
  EXPECT_EQ(g.position(2), Vec3(2, 0, 0));
  EXPECT_TRUE(g.has_edge(0, 1));
  EXPECT_TRUE(g.has_edge(1, 2));
  EXPECT_FALSE(g.has_edge(2, 3));
  EXPECT_EQ(g.edge_count(), 2u);
  EXPECT_EQ(b.samples(), 0u) << "step() is not counted in samples()";
}

// extend(n) draws n points of the box from Rng(seed) (uniform_in, in order): it grows exactly
// the roadmap that stepping those points one by one grows, and counts the invalid ones too.
TEST(DenseBuilder, ExtendInsertsTheValidSamplesOfTheSeededStream) {
  const Scene scene = small_box_scene();
  BuildOptions options;
  options.seed = 11;
  DenseBuilder extended(scene, options);
  extended.extend(300);
  EXPECT_EQ(extended.samples(), 300u);

  DenseBuilder stepped(scene, options);
  scene_files::Rng rng(options.seed);
  std::size_t invalid = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 q = rng.uniform_in(scene.config().bounds);
    invalid += scene.point_valid(q) ? 0 : 1;
    stepped.step(q);
  }
  EXPECT_GT(invalid, 0u) << "no sample fell by the wall: the test would not see invalid samples";
  EXPECT_EQ(extended.roadmap().vertex_count(), 301 - invalid);
  EXPECT_EQ(test::fingerprint(extended.roadmap()), test::fingerprint(stepped.roadmap()));
  EXPECT_GT(extended.roadmap().edge_count(), 0u);

  // The same points inserted into a bare DeltaPrm after the root give the same graph again.
  DeltaPrm prm(scene, scene.config().dense_delta);
  prm.insert(scene.config().root, scene.visibility().visible_pois(scene.config().root));
  scene_files::Rng again(options.seed);
  for (int i = 0; i < 300; ++i) {
    const Vec3 q = again.uniform_in(scene.config().bounds);
    if (scene.point_valid(q)) prm.insert(q, scene.visibility().visible_pois(q));
  }
  EXPECT_EQ(test::fingerprint(extended.roadmap()), test::fingerprint(prm.graph()));
}

TEST(DenseBuilder, ResumedBuilderHoldsTheGivenRoadmapAndGoesOnInTheStream) {
  const Scene scene = small_box_scene();
  DenseBuilder first(scene, BuildOptions{});
  first.extend(100);
  Roadmap copy = first.roadmap();
  DenseBuilder resumed(scene, BuildOptions{}, std::move(copy), 100);
  EXPECT_EQ(resumed.samples(), 100u);
  EXPECT_TRUE(resumed.roadmap().same_changes_as(first.roadmap()));
  first.extend(50);
  resumed.extend(50);
  EXPECT_EQ(resumed.samples(), 150u);
  EXPECT_EQ(test::fingerprint(resumed.roadmap()), test::fingerprint(first.roadmap()));
  // Resumed at the wrong place in the stream, it draws other samples.
  DenseBuilder misplaced(scene, BuildOptions{}, Roadmap(first.roadmap()), 0);
  DenseBuilder reference(scene, BuildOptions{}, Roadmap(first.roadmap()), 150);
  misplaced.extend(20);
  reference.extend(20);
  EXPECT_NE(test::fingerprint(misplaced.roadmap()), test::fingerprint(reference.roadmap()));
}

}  // namespace
}  // namespace ispars::planning
