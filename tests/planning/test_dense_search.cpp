// DenseSearch (dense_search.hpp): settling in (distance, id) order, the strict bound, keep(),
// paths, and the reuse of its arrays from one search to the next on a growing graph.

#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "ispars/planning/search/dense_search.hpp"
#include "ispars/planning/search/graph_search.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

using Settled = std::pair<double, VertexId>;

Roadmap roadmap_of(const std::vector<Vec3>& points, const std::vector<std::pair<VertexId, VertexId>>& edges) {
  Roadmap r(0);
  for (const Vec3& p : points) r.add_vertex(p, std::vector<PoiId>{});
  for (const auto& [u, v] : edges) r.add_edge(u, v);
  return r;
}

// 0 at the origin; 1 (1,0,0) and 2 (0,1,0) both 1 away; 3 (2,0,0) behind 1; 4 (5,0,0) behind 3.
Roadmap fan() {
  return roadmap_of({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(5, 0, 0)},
                    {{0, 2}, {0, 1}, {1, 3}, {2, 3}, {3, 4}});
}

std::vector<Settled> settle_all(DenseSearch& s, const Roadmap& g, double bound) {
  std::vector<Settled> out;
  for (Settled x = s.settle_next(g, bound); x.second != kNoVertex; x = s.settle_next(g, bound)) out.push_back(x);
  return out;
}

TEST(DenseSearch, SettlesByDistanceThenId) {
  const Roadmap g = fan();
  DenseSearch s;
  s.start(g.vertex_count(), 0);
  const std::vector<Settled> order = settle_all(s, g, INFINITY);
  EXPECT_EQ(order, (std::vector<Settled>{{0.0, 0}, {1.0, 1}, {1.0, 2}, {2.0, 3}, {5.0, 4}}));
  EXPECT_EQ(s.path_to(0, 4), (std::vector<VertexId>{0, 1, 3, 4}));
  EXPECT_EQ(s.path_to(0, 0), std::vector<VertexId>{0});
  EXPECT_DOUBLE_EQ(s.distance(4), 5.0);
  EXPECT_EQ(s.distance(99), INFINITY) << "beyond the arrays: never reached";
}

TEST(DenseSearch, BoundIsStrictAndEndsTheSearch) {
  const Roadmap g = fan();
  DenseSearch s;
  s.start(g.vertex_count(), 0);
  // Vertices at exactly the bound (3 at 2) are neither settled nor reached.
  EXPECT_EQ(settle_all(s, g, 2.0), (std::vector<Settled>{{0.0, 0}, {1.0, 1}, {1.0, 2}}));
  EXPECT_EQ(s.distance(3), INFINITY);
  EXPECT_EQ(s.reached(), (std::vector<VertexId>{0, 2, 1}));
  // Once it returned nothing, it stays empty even under a larger bound.
  EXPECT_EQ(s.settle_next(g, INFINITY).second, kNoVertex);
  // Not even the source is below a bound of 0.
  s.start(g.vertex_count(), 0);
  EXPECT_EQ(s.settle_next(g, 0.0), (Settled{INFINITY, kNoVertex}));
}

TEST(DenseSearch, ABetterRouteFoundLaterReplacesTheFirstAndIsSettledOnce) {
  // From 0: x (1,0,0) is settled first and reaches c (1,3,0) at 4; y (0,1.5,0) comes next and
  // reaches it at 1.5 + sqrt(3.25) = 3.30. c is settled once, at 3.30, through y.
  const Roadmap g =
      roadmap_of({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1.5, 0), Vec3(1, 3, 0)}, {{0, 1}, {0, 2}, {1, 3}, {2, 3}});
  DenseSearch s;
  s.start(g.vertex_count(), 0);
  const std::vector<Settled> order = settle_all(s, g, INFINITY);
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(order[3].second, 3u);
  EXPECT_DOUBLE_EQ(order[3].first, 1.5 + std::sqrt(3.25));
  EXPECT_EQ(s.path_to(0, 3), (std::vector<VertexId>{0, 2, 3}));
}

TEST(DenseSearch, KeepRefusesNeighboursAndForcesADetour) {
  const Roadmap g = fan();
  DenseSearch s;
  s.start(g.vertex_count(), 0);
  const auto not_1 = [](VertexId v, double) { return v != 1; };
  std::vector<Settled> order;
  for (Settled x = s.settle_next(g, INFINITY, not_1); x.second != kNoVertex; x = s.settle_next(g, INFINITY, not_1)) {
    order.push_back(x);
  }
  ASSERT_EQ(order.size(), 4u);
  EXPECT_EQ(s.distance(1), INFINITY);
  EXPECT_DOUBLE_EQ(s.distance(3), 1.0 + std::sqrt(5.0));
  EXPECT_EQ(s.path_to(0, 4), (std::vector<VertexId>{0, 2, 3, 4}));
}

TEST(DenseSearch, ANewSearchForgetsTheLastOneAndGrowsWithTheGraph) {
  Roadmap g = fan();
  DenseSearch s;
  s.start(g.vertex_count(), 0);
  (void)settle_all(s, g, INFINITY);
  // The graph grows: 5 at (5,1,0) joined to 4 only. A search from 4 knows nothing of the last.
  g.add_vertex(Vec3(5, 1, 0), std::vector<PoiId>{});
  g.add_edge(4, 5);
  s.start(g.vertex_count(), 4);
  EXPECT_EQ(s.distance(0), INFINITY);
  EXPECT_EQ(s.distance(4), 0.0);
  EXPECT_EQ(s.reached(), std::vector<VertexId>{4});
  EXPECT_EQ(settle_all(s, g, 2.0), (std::vector<Settled>{{0.0, 4}, {1.0, 5}}));
  EXPECT_EQ(s.path_to(4, 5), (std::vector<VertexId>{4, 5}));
}

TEST(DenseSearch, AgreesWithDijkstraOnRandomGraphs) {
  scene_files::Rng rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<Vec3> points;
    std::vector<std::pair<VertexId, VertexId>> edges;
    for (int i = 0; i < 60; ++i) points.push_back(rng.uniform_in({Vec3(0, 0, 0), Vec3(4, 4, 1)}));
    for (VertexId u = 0; u < points.size(); ++u) {
      for (VertexId v = u + 1; v < points.size(); ++v) {
        if ((points[u] - points[v]).norm() < 1.0) edges.emplace_back(u, v);
      }
    }
    const Roadmap g = roadmap_of(points, edges);
    DenseSearch s;  // one search object for every source: the reuse is under test too
    for (VertexId source = 0; source < 5; ++source) {
      const std::vector<double> expected = shortest_distances(g, source);
      s.start(g.vertex_count(), source);
      const std::vector<Settled> order = settle_all(s, g, INFINITY);
      for (std::size_t i = 1; i < order.size(); ++i) EXPECT_LE(order[i - 1], order[i]);
      std::size_t reachable = 0, wrong = 0;
      for (VertexId v = 0; v < g.vertex_count(); ++v) {
        reachable += std::isfinite(expected[v]) ? 1 : 0;
        const bool right =
            std::isfinite(expected[v]) ? std::abs(s.distance(v) - expected[v]) <= 1e-12 : s.distance(v) == INFINITY;
        if (!right && wrong++ == 0) {
          ADD_FAILURE() << "trial " << trial << " source " << source << " v " << v << ": " << s.distance(v) << " for "
                        << expected[v];
        }
      }
      EXPECT_EQ(wrong, 0u);
      EXPECT_EQ(order.size(), reachable);
    }
  }
}

}  // namespace
}  // namespace ispars::planning
