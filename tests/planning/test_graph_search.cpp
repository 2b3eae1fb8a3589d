// Dijkstra over a roadmap, and the reusable early-stopping DenseSearch, against each other.

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/planning/search/dense_search.hpp"
#include "ispars/planning/search/graph_search.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

Roadmap random_graph(std::uint64_t seed, int vertices, int edges) {
  scene_files::Rng rng(seed);
  Roadmap g(0);
  for (int i = 0; i < vertices; ++i) g.add_vertex(rng.uniform_in({Vec3(0, 0, 0), Vec3(10, 10, 10)}), {});
  for (int i = 0; i < edges; ++i) {
    g.add_edge(static_cast<VertexId>(rng.below(static_cast<std::uint64_t>(vertices))),
               static_cast<VertexId>(rng.below(static_cast<std::uint64_t>(vertices))));
  }
  return g;
}

TEST(GraphSearch, ShortestDistancesOnAHandMadeGraph) {
  Roadmap g(0);
  g.add_vertex(Vec3(0, 0, 0), {});
  g.add_vertex(Vec3(3, 0, 0), {});
  g.add_vertex(Vec3(3, 4, 0), {});
  g.add_vertex(Vec3(9, 9, 9), {});
  g.add_edge(0, 1);
  g.add_edge(1, 2);
  g.add_edge(0, 2);
  const auto d = shortest_distances(g, 0);
  EXPECT_EQ(d[1], 3.0);
  EXPECT_EQ(d[2], 5.0);  // direct beats 3 + 4
  EXPECT_TRUE(std::isinf(d[3]));
}

TEST(GraphSearch, DenseSearchSettlesInOrderWithTheSameDistancesAndReusesItsArrays) {
  const Roadmap g = random_graph(3, 300, 900);
  DenseSearch search;
  for (VertexId source : {0u, 17u, 299u, 0u}) {
    const auto expected = shortest_distances(g, source);
    search.start(g.vertex_count(), source);
    double last = 0.0;
    std::size_t settled = 0;
    for (;;) {
      const auto [d, v] = search.settle_next(g, INFINITY);
      if (v == kNoVertex) break;
      EXPECT_GE(d, last);
      EXPECT_DOUBLE_EQ(d, expected[v]);
      last = d;
      ++settled;
      // The path it reports has the settled length.
      const auto path = search.path_to(source, v);
      double length = 0.0;
      for (std::size_t i = 1; i < path.size(); ++i) length += (g.position(path[i]) - g.position(path[i - 1])).norm();
      EXPECT_NEAR(length, d, 1e-9);
    }
    std::size_t reachable = 0;
    for (const double d : expected) reachable += std::isfinite(d);
    EXPECT_EQ(settled, reachable);
  }
}

TEST(GraphSearch, DenseSearchStopsAtTheBound) {
  const Roadmap g = random_graph(4, 200, 600);
  DenseSearch search;
  search.start(g.vertex_count(), 0);
  const auto expected = shortest_distances(g, 0);
  std::size_t settled = 0;
  for (;;) {
    const auto [d, v] = search.settle_next(g, 5.0);
    if (v == kNoVertex) break;
    EXPECT_LT(d, 5.0);
    ++settled;
  }
  std::size_t below = 0;
  for (const double d : expected) below += d < 5.0;
  EXPECT_EQ(settled, below);
}

}  // namespace
}  // namespace ispars::planning
