// DeltaPrm (the dense roadmap G_d): an inserted vertex is joined to exactly the vertices within
// delta (<= delta) whose segment to it is valid; the index of a given graph is rebuilt; within()
// is nearest first.

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "ispars/planning/builders/delta_prm.hpp"
#include "ispars/scene_files/random.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// open_scene's wall: the square x = 2.5, |y|, |z| <= 1, robot radius 0.1.
const Scene& wall_scene() {
  static const Scene scene = test::open_scene(1.0, 3.0, true);
  return scene;
}

TEST(DeltaPrm, StartsEmptyWithTheScenePois) {
  const DeltaPrm prm(wall_scene(), 1.0);
  EXPECT_EQ(prm.graph().vertex_count(), 0u);
  EXPECT_EQ(prm.graph().edge_count(), 0u);
  EXPECT_EQ(prm.graph().visibility_table().poi_count(), wall_scene().pois().size());
  EXPECT_DOUBLE_EQ(prm.delta(), 1.0);
}

TEST(DeltaPrm, JoinsPairsWithinDeltaInclusiveAndNoFarther) {
  DeltaPrm prm(wall_scene(), 1.0);
  const std::vector<PoiId> none;
  const std::vector<PoiId> first{0};
  EXPECT_EQ(prm.insert(Vec3(0, 0, 0), first), 0u);
  EXPECT_EQ(prm.insert(Vec3(0.5, 0, 0), none), 1u);
  EXPECT_EQ(prm.insert(Vec3(1.0, 0, 0), none), 2u);   // exactly delta from vertex 0
  EXPECT_EQ(prm.insert(Vec3(1.75, 0, 0), none), 3u);  // 1.75 from 0, 1.25 from 1, 0.75 from 2
  const Roadmap& g = prm.graph();
  EXPECT_TRUE(g.has_edge(0, 1));
  EXPECT_TRUE(g.has_edge(0, 2));
  EXPECT_TRUE(g.has_edge(1, 2));
  EXPECT_TRUE(g.has_edge(2, 3));
  EXPECT_FALSE(g.has_edge(0, 3));
  EXPECT_FALSE(g.has_edge(1, 3));
  EXPECT_EQ(g.edge_count(), 4u);
  EXPECT_EQ(g.component_count(), 1u);
  // The new vertex is the second end of each of its edges, and carries its POIs.
  for (const RoadmapEdge e : g.edges()) EXPECT_LT(e.u, e.v);
  EXPECT_EQ(g.visibility_table().ids(0), first);
  EXPECT_TRUE(g.visibility_table().ids(1).empty());
}

TEST(DeltaPrm, SkipsAPairWithinDeltaWhoseSegmentCrossesTheWall) {
  DeltaPrm prm(wall_scene(), 1.0);
  const std::vector<PoiId> none;
  const VertexId a = prm.insert(Vec3(2.2, 0, 0), none);
  const VertexId b = prm.insert(Vec3(2.8, 0, 0), none);    // 0.6 apart, the wall between
  const VertexId c = prm.insert(Vec3(2.2, 0, 1.3), none);  // above the wall's top edge (z = 1)
  const VertexId d = prm.insert(Vec3(2.8, 0, 1.3), none);
  ASSERT_FALSE(wall_scene().segment_valid(prm.graph().position(a), prm.graph().position(b)));
  const Roadmap& g = prm.graph();
  EXPECT_FALSE(g.has_edge(a, b));
  EXPECT_TRUE(g.has_edge(c, d));
  EXPECT_FALSE(g.has_edge(a, c));  // 1.3 apart
  EXPECT_EQ(g.edge_count(), 1u);
}

// Random points around the wall: the edge set is exactly the brute-force one.
TEST(DeltaPrm, EdgesAreExactlyTheValidPairsWithinDelta) {
  const Scene& scene = wall_scene();
  const double delta = 0.8;
  DeltaPrm prm(scene, delta);
  scene_files::Rng rng(7);
  const std::vector<PoiId> none;
  std::vector<Vec3> points;
  while (points.size() < 150) {
    const Vec3 q(rng.uniform(1.0, 4.0), rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5));
    if (!scene.point_valid(q)) continue;
    points.push_back(q);
    prm.insert(q, none);
  }
  const Roadmap& g = prm.graph();
  std::size_t expected_edges = 0, blocked = 0, wrong = 0;
  for (VertexId u = 0; u < points.size(); ++u) {
    for (VertexId v = u + 1; v < points.size(); ++v) {
      const bool near = (points[u] - points[v]).norm() <= delta;
      const bool valid = near && scene.segment_valid(points[u], points[v]);
      if (near && !valid) ++blocked;
      expected_edges += valid ? 1 : 0;
      if (g.has_edge(u, v) != valid && wrong++ == 0) ADD_FAILURE() << "first wrong pair " << u << "-" << v;
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(g.edge_count(), expected_edges);
  EXPECT_GT(blocked, 0u);  // the wall did block some near pairs
  EXPECT_GT(expected_edges, 0u);
}

TEST(DeltaPrm, GivenGraphIsIndexedSoNewVerticesJoinItsVertices) {
  Roadmap given(wall_scene().pois().size());
  const std::vector<PoiId> none;
  given.add_vertex(Vec3(0, 0, 0), none);
  given.add_vertex(Vec3(5, 0, 0), none);
  DeltaPrm prm(wall_scene(), 1.0, std::move(given));
  EXPECT_EQ(prm.graph().vertex_count(), 2u);
  EXPECT_EQ(prm.graph().edge_count(), 0u);  // the given graph is kept as it is
  const VertexId v = prm.insert(Vec3(0.6, 0, 0), none);
  EXPECT_EQ(v, 2u);
  EXPECT_TRUE(prm.graph().has_edge(0, 2));
  EXPECT_FALSE(prm.graph().has_edge(1, 2));
  EXPECT_EQ(prm.graph().edge_count(), 1u);
}

TEST(DeltaPrm, WithinIsNearestFirstAndInclusive) {
  DeltaPrm prm(wall_scene(), 1.0);
  const std::vector<PoiId> none;
  prm.insert(Vec3(0, 0, 0), none);
  prm.insert(Vec3(0, 0, 0.3), none);
  prm.insert(Vec3(0, 0.1, 0), none);
  prm.insert(Vec3(3, 0, 0), none);
  std::vector<std::pair<double, std::uint32_t>> out{{9.0, 9u}};  // replaced, not appended to
  prm.within(Vec3(0, 0, 0), 0.3, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].second, 0u);
  EXPECT_EQ(out[1].second, 2u);
  EXPECT_EQ(out[2].second, 1u);
  EXPECT_DOUBLE_EQ(out[0].first, 0.0);
  EXPECT_DOUBLE_EQ(out[1].first, 0.1);
  EXPECT_DOUBLE_EQ(out[2].first, 0.3);
  prm.within(Vec3(10, 0, 0), 1.0, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace ispars::planning
