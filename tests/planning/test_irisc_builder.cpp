// IriscBuilder (the IRIS-C baseline) step by step on hand-placed samples: steering by at most
// eta = delta from the nearest vertex, a state that sees a new POI always admitted and any other
// with probability p_accept, an invalid state or blocked steering segment dropped, and an
// admitted state joined to every vertex within r_RRG = Delta in view. (Determinism and
// extend(a) + extend(b) = extend(a + b) are checked for every method in test_roadmap_builder.)

#include <gtest/gtest.h>

#include "ispars/planning/builders/irisc_builder.hpp"
#include "ispars/scene_files/random.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// open_scene (with its wall at x = 2.5 when asked) with two POIs read from a file, at (2, 0, 0)
// and (-2, 0, 0), and sensor range 1.2: the root sees neither, (1, 0, 0) sees POI 0 and
// (-1, 0, 0) POI 1.
Scene poi_scene(double delta, double big_delta, bool wall) {
  static const test::TempDir dir;
  const Scene base = test::open_scene(delta, big_delta, wall);
  scene_files::SceneConfig config = base.config();
  config.sensor_range = 1.2;
  config.pois.file = dir.write("pois.txt", "2 0 0\n-2 0 0\n");
  return Scene::build(config, base.mesh());
}

BuildOptions with_p_accept(double p) {
  BuildOptions options;
  options.p_accept = p;
  return options;
}

TEST(IriscBuilder, StartsWithTheRootAndWhatItSees) {
  const Scene scene = poi_scene(1.0, 1.5, false);
  ASSERT_EQ(scene.pois().size(), 2u);
  const IriscBuilder b(scene, BuildOptions{});
  ASSERT_EQ(b.roadmap().vertex_count(), 1u);
  EXPECT_EQ(b.roadmap().position(0), scene.config().root);
  EXPECT_EQ(b.roadmap().covered_pois(), 0u);
  EXPECT_EQ(b.samples(), 0u);
}

TEST(IriscBuilder, SteersByEtaAndAdmitsOnlyStatesSeeingNewPois) {
  const Scene scene = poi_scene(1.0, 1.5, false);
  IriscBuilder b(scene, with_p_accept(0.0));
  b.step(Vec3(10, 0, 0));  // from the root, eta = 1 toward the sample: (1, 0, 0) sees POI 0
  ASSERT_EQ(b.roadmap().vertex_count(), 2u);
  EXPECT_EQ(b.roadmap().position(1), Vec3(1, 0, 0));
  EXPECT_EQ(b.roadmap().visibility_table().ids(1), std::vector<PoiId>{0});
  EXPECT_TRUE(b.roadmap().has_edge(0, 1));
  b.step(Vec3(10, 0, 0));  // from (1, 0, 0) to (2, 0, 0): sees POI 0 again, nothing new
  EXPECT_EQ(b.roadmap().vertex_count(), 2u);
  b.step(Vec3(0, 0.5, 0));  // within eta: the sample itself, which sees nothing
  EXPECT_EQ(b.roadmap().vertex_count(), 2u);
  b.step(Vec3(-10, 0, 0));  // from the root to (-1, 0, 0): sees POI 1
  ASSERT_EQ(b.roadmap().vertex_count(), 3u);
  EXPECT_EQ(b.roadmap().position(2), Vec3(-1, 0, 0));
  EXPECT_TRUE(b.roadmap().has_edge(0, 2));
  EXPECT_FALSE(b.roadmap().has_edge(1, 2));  // 2 apart, beyond Delta
  EXPECT_EQ(b.roadmap().covered_pois(), 2u);
  EXPECT_EQ(b.samples(), 0u) << "step() is not counted in samples()";
}

TEST(IriscBuilder, PAcceptOneAdmitsEveryValidStateAndASampleWithinEtaAsItIs) {
  const Scene scene = poi_scene(1.0, 1.5, false);
  IriscBuilder b(scene, with_p_accept(1.0));
  b.step(Vec3(0, 0.5, 0));
  ASSERT_EQ(b.roadmap().vertex_count(), 2u);
  EXPECT_EQ(b.roadmap().position(1), Vec3(0, 0.5, 0));
  b.step(Vec3(0, 3, 0));  // nearest is (0, 0.5, 0): steered to (0, 1.5, 0), 1.5 from the root
  ASSERT_EQ(b.roadmap().vertex_count(), 3u);
  EXPECT_EQ(b.roadmap().position(2), Vec3(0, 1.5, 0));
  EXPECT_TRUE(b.roadmap().has_edge(1, 2));
  EXPECT_TRUE(b.roadmap().has_edge(0, 2)) << "exactly Delta away: within r_RRG";
  EXPECT_EQ(b.roadmap().edge_count(), 3u);
}

TEST(IriscBuilder, DropsAnInvalidStateAndABlockedSteeringSegment) {
  const Scene scene = poi_scene(1.0, 1.5, true);  // wall at x = 2.5, robot radius 0.1
  IriscBuilder b(scene, with_p_accept(1.0));
  b.step(Vec3(1, 0, 0));
  b.step(Vec3(2, 0, 0));
  ASSERT_EQ(b.roadmap().vertex_count(), 3u);
  b.step(Vec3(2.45, 0, 0));  // within the robot radius of the wall
  EXPECT_EQ(b.roadmap().vertex_count(), 3u);
  b.step(Vec3(3, 0, 0));  // valid, but the steering segment from (2, 0, 0) crosses the wall
  EXPECT_EQ(b.roadmap().vertex_count(), 3u);
  b.step(Vec3(2, 0, 0.8));  // valid and in view: admitted
  EXPECT_EQ(b.roadmap().vertex_count(), 4u);
}

// With delta <= Delta the steering parent is within r_RRG, so every admitted state is joined to
// exactly the earlier vertices within Delta whose segment is valid.
TEST(IriscBuilder, EdgesAreExactlyTheValidPairsWithinRadius) {
  const Scene scene = poi_scene(0.7, 1.2, true);
  IriscBuilder b(scene, with_p_accept(1.0));
  scene_files::Rng rng(3);
  for (int i = 0; i < 400; ++i) b.step(Vec3(rng.uniform(-1, 5), rng.uniform(-2, 2), rng.uniform(-2, 2)));
  const Roadmap& g = b.roadmap();
  ASSERT_GT(g.vertex_count(), 30u);
  std::size_t expected = 0, blocked = 0, wrong = 0;
  for (VertexId u = 0; u < g.vertex_count(); ++u) {
    EXPECT_TRUE(scene.point_valid(g.position(u)));
    for (VertexId v = u + 1; v < g.vertex_count(); ++v) {
      const bool near = (g.position(u) - g.position(v)).norm() <= 1.2;
      const bool valid = near && scene.segment_valid(g.position(u), g.position(v));
      blocked += near && !valid ? 1 : 0;
      expected += valid ? 1 : 0;
      if (g.has_edge(u, v) != valid && wrong++ == 0) ADD_FAILURE() << "first wrong pair " << u << "-" << v;
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(g.edge_count(), expected);
  EXPECT_GT(blocked, 0u);
  EXPECT_EQ(g.component_count(), 1u) << "every state is joined to its steering parent";
}

}  // namespace
}  // namespace ispars::planning
