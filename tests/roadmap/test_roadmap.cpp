// Roadmap: vertices, edges, components and the change log a consumer replays.

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {
namespace {

std::vector<RoadmapChange> changes_since(const Roadmap& g, std::uint64_t version) {
  std::vector<RoadmapChange> out;
  g.for_each_change(version, g.version(), [&](const RoadmapChange& c) { out.push_back(c); });
  return out;
}

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
  const auto changes = changes_since(g, v);
  ASSERT_EQ(changes.size(), 3u);
  EXPECT_EQ(changes[0].kind, RoadmapChange::Kind::edge);
  EXPECT_EQ(changes[0].index, 0u);
  EXPECT_EQ(changes[1].kind, RoadmapChange::Kind::vertex);
  EXPECT_EQ(changes[1].index, 2u);
  EXPECT_EQ(changes[2].kind, RoadmapChange::Kind::edge);
  EXPECT_EQ(changes[2].index, 1u);
  EXPECT_TRUE(changes_since(g, g.version()).empty());
  EXPECT_TRUE(changes_since(g, 1000).empty());
  EXPECT_EQ(changes_since(g, 0).size(), g.version());
}

// The log is not stored but placed from each vertex's edge count: every interleaving must come
// back as it was made, from every version. The hard cases: edges before any second vertex, long
// runs of edges, several vertices in a row, and a vertex as the very last change.
TEST(Roadmap, TheChangeLogComesBackAsMadeFromEveryVersionForAnyInterleaving) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    Roadmap g(0);
    std::vector<RoadmapChange> made;
    for (int step = 0; step < 300; ++step) {
      const bool vertex = g.vertex_count() < 2 || rng() % (seed % 4 + 2) == 0;
      if (vertex) {
        const VertexId id = g.add_vertex(Vec3(rng() % 100, rng() % 100, rng() % 100), {});
        made.push_back({RoadmapChange::Kind::vertex, id});
      } else {
        const auto n = static_cast<VertexId>(g.vertex_count());
        const VertexId a = rng() % n;
        const VertexId b = rng() % n;
        if (g.add_edge(a, b))
          made.push_back({RoadmapChange::Kind::edge, static_cast<std::uint32_t>(g.edge_count() - 1)});
      }
    }
    ASSERT_EQ(g.version(), made.size());
    for (std::uint64_t from = 0; from <= made.size(); ++from) {
      const auto got = changes_since(g, from);
      ASSERT_EQ(got.size(), made.size() - from) << "seed " << seed << " from " << from;
      for (std::size_t k = 0; k < got.size(); ++k) {
        ASSERT_EQ(got[k].kind, made[from + k].kind) << "seed " << seed << " at " << from + k;
        ASSERT_EQ(got[k].index, made[from + k].index) << "seed " << seed << " at " << from + k;
      }
      if (from < made.size()) {
        EXPECT_EQ(g.change(from).kind, made[from].kind);
        EXPECT_EQ(g.change(from).index, made[from].index);
      }
    }
  }
}

// Costs are computed, not stored: from either end, in the edge list and in the neighbour lists,
// a cost must be the very double |u - v| computed when the edge was made.
TEST(Roadmap, AnEdgesCostIsTheSameDoubleFromEitherEndAndInTheEdgeList) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-1e3, 1e3);
  Roadmap g(0);
  for (int i = 0; i < 200; ++i) g.add_vertex(Vec3(coordinate(rng), coordinate(rng), coordinate(rng)), {});
  for (int i = 0; i < 2000; ++i) g.add_edge(rng() % 200, rng() % 200);
  for (std::size_t i = 0; i < g.edge_count(); ++i) {
    const RoadmapEdge e = g.edges()[i];
    const double made = (g.position(e.u) - g.position(e.v)).norm();
    ASSERT_EQ(e.cost, made);
    ASSERT_EQ(g.edge(i).cost, made);
    const auto cost_from = [&](VertexId a, VertexId b) {
      for (const Neighbor& n : g.neighbors(a)) {
        if (n.vertex == b) return n.cost;
      }
      return -1.0;
    };
    ASSERT_EQ(cost_from(e.u, e.v), made);
    ASSERT_EQ(cost_from(e.v, e.u), made);
  }
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

// New POIs (an inspection task) seen by vertices already built: coverage counts them, the change
// log does not move, and the roadmap equals one built with every POI from the start.
TEST(Roadmap, NewPoisSeenByBuiltVerticesCountAndLeaveTheLogAlone) {
  Roadmap g(3);
  g.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{0});
  g.add_vertex(Vec3(1, 0, 0), std::vector<PoiId>{1});
  g.add_vertex(Vec3(9, 0, 0), std::vector<PoiId>{2});
  g.add_edge(0, 1);
  const std::uint64_t version = g.version();
  g.widen_pois(100);
  g.add_visible(1, std::vector<PoiId>{70, 99});
  g.add_visible(2, std::vector<PoiId>{3});
  EXPECT_EQ(g.poi_count(), 100u);
  EXPECT_EQ(g.version(), version);
  EXPECT_EQ(g.covered_pois(), 6u);
  EXPECT_EQ(g.covered_pois_in_component_of(0), 4u);
  Roadmap wide(100);
  wide.add_vertex(Vec3(0, 0, 0), std::vector<PoiId>{0});
  wide.add_vertex(Vec3(1, 0, 0), std::vector<PoiId>{1, 70, 99});
  wide.add_vertex(Vec3(9, 0, 0), std::vector<PoiId>{2, 3});
  wide.add_edge(0, 1);
  EXPECT_TRUE(g.same_changes_as(wide));
  EXPECT_THROW(g.add_visible(3, std::vector<PoiId>{0}), std::out_of_range);
  EXPECT_THROW(g.widen_pois(99), std::invalid_argument);
}

}  // namespace
}  // namespace ispars
