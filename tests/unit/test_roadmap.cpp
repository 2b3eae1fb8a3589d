// Roadmap: vertices, edges, components and the change log a consumer replays.

#include <gtest/gtest.h>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {
namespace {

TEST(Roadmap, EdgesAreUndirectedUniqueAndCostTheirLength) {
  Roadmap g(10);
  const VertexId a = g.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{1, 3});
  const VertexId b = g.add_vertex(Vec3(3, 4, 0), std::vector<PoiId>{3, 9});
  EXPECT_TRUE(g.add_edge(a, b));
  EXPECT_FALSE(g.add_edge(b, a));  // already there
  EXPECT_FALSE(g.add_edge(a, a));  // no loops
  ASSERT_EQ(g.edge_count(), 1u);
  EXPECT_EQ(g.edges()[0].cost, 5.0);
  EXPECT_TRUE(g.has_edge(b, a));
  EXPECT_EQ(g.neighbors(a).size(), 1u);
  EXPECT_EQ(g.visibility_table().ids(b), (std::vector<PoiId>{3, 9}));
  EXPECT_EQ(g.covered_pois(), 3u);
}

TEST(Roadmap, ComponentsFollowEdges) {
  Roadmap g(0);
  for (int i = 0; i < 6; ++i) g.add_vertex(Vec3(i, 0, 0), {});
  EXPECT_EQ(g.component_count(), 6u);
  g.add_edge(0, 1);
  g.add_edge(2, 3);
  g.add_edge(3, 4);
  EXPECT_EQ(g.component_count(), 3u);
  EXPECT_TRUE(g.same_component(2, 4));
  EXPECT_FALSE(g.same_component(1, 2));
  g.add_edge(1, 4);
  EXPECT_TRUE(g.same_component(0, 2));
  EXPECT_FALSE(g.same_component(0, 5));
  EXPECT_EQ(g.component_count(), 2u);
}

TEST(Roadmap, ChangeLogReplaysEverythingAfterAVersion) {
  Roadmap g(4);
  g.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{0});
  g.add_vertex(Vec3(1, 0, 0), {});
  const std::uint64_t v = g.version();
  EXPECT_EQ(v, 2u);
  g.add_edge(0, 1);
  g.add_vertex(Vec3(2, 0, 0), {});
  g.add_edge(1, 2);
  g.add_edge(2, 1);  // no change: no log entry
  const auto changes = g.changes_since(v);
  ASSERT_EQ(changes.size(), 3u);
  EXPECT_EQ(changes[0].kind, RoadmapChange::Kind::edge);
  EXPECT_EQ(changes[0].index, 0u);
  EXPECT_EQ(changes[1].kind, RoadmapChange::Kind::vertex);
  EXPECT_EQ(changes[1].index, 2u);
  EXPECT_EQ(changes[2].kind, RoadmapChange::Kind::edge);
  EXPECT_EQ(changes[2].index, 1u);
  EXPECT_TRUE(g.changes_since(g.version()).empty());
  EXPECT_TRUE(g.changes_since(1000).empty());
  EXPECT_EQ(g.changes_since(0).size(), g.version());
}

TEST(Roadmap, RootComponentCoverage) {
  Roadmap g(8);
  g.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{0});
  g.add_vertex(Vec3(1, 0, 0), std::vector<PoiId>{1, 2});
  g.add_vertex(Vec3(9, 0, 0), std::vector<PoiId>{5, 6, 7});
  g.add_edge(0, 1);
  EXPECT_EQ(g.covered_pois(), 6u);
  EXPECT_EQ(g.covered_pois_in_component_of(0), 3u);
}

}  // namespace
}  // namespace ispars
