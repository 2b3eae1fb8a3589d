// Corridor densification (tour_corridor.hpp): the tube's samples are uniform at the asked density
// and lie within r of the path; the base graph keeps its ids and edges; the flown path is a walk
// of the new graph; every new edge is within the join radius and collision-free; the same seed
// gives the same graph.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "ispars/tour/tour_corridor.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

double distance_to_path(const Vec3& q, const std::vector<Vec3>& stops) {
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
    const Vec3 d = stops[i + 1] - stops[i];
    const double t = d.squaredNorm() > 0 ? std::clamp((q - stops[i]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (q - (stops[i] + t * d)).norm());
  }
  return best;
}

// A base graph of two vertices, the root and a point 10 m away, joined.
struct Base {
  InspectionGraph graph;
  std::vector<Vec3> positions{Vec3(0, 0, 0), Vec3(10, 0, 0)};
};

Base two_vertices() {
  Base b;
  const std::vector<RoadmapEdge> edges{{0, 1, 10.0}};
  b.graph = InspectionGraph::from_edges(2, edges, {{}, {}}, 3);
  return b;
}

TEST(TourCorridor, SamplesAreUniformInTheTubeAndTheBaseStaysAsItWas) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Base base = two_vertices();
  // Out and back along one segment: the tube is one capsule, drawn over twice.
  const std::vector<Vec3> stops{base.positions[0], base.positions[1], base.positions[0]};
  const std::vector<VertexId> ids{0, 1, 0};
  CorridorOptions o;
  o.radius = 1.0;
  o.join_radius = 1.5;
  o.density = 20.0;
  const CorridorGraph g = corridor_graph(scene, base.graph, base.positions, stops, ids, o);
  const double volume = std::numbers::pi * 10.0 + 4.0 / 3.0 * std::numbers::pi;  // one capsule
  EXPECT_NEAR(static_cast<double>(g.samples), o.density * volume, 4.0 * std::sqrt(o.density * volume))
      << "the union's volume, not the two capsules' sum";
  ASSERT_EQ(g.graph.vertex_count(), 2 + g.samples);
  for (std::size_t v = 2; v < g.positions.size(); ++v) EXPECT_LE(distance_to_path(g.positions[v], stops), 1.0 + 1e-12);
  EXPECT_EQ(g.walk, ids);
  EXPECT_NEAR(g.graph.edge_cost(0, 1), 10.0, 1e-12);
  for (const RoadmapEdge& e : g.graph.edges()) {
    if (e.u < 2 && e.v < 2) continue;  // the base edge and the flown segments
    EXPECT_LE(e.cost, o.join_radius + 1e-12);
    EXPECT_NEAR(e.cost, (g.positions[e.u] - g.positions[e.v]).norm(), 1e-12);
  }
  const CorridorGraph again = corridor_graph(scene, base.graph, base.positions, stops, ids, o);
  EXPECT_EQ(again.positions, g.positions);
  EXPECT_EQ(again.graph.edge_count(), g.graph.edge_count());
}

TEST(TourCorridor, NoJoinCrossesAWallAndAStopOffTheGraphBecomesAVertex) {
  const Scene scene = test::open_scene(1.0, 1.5, /*wall=*/true);
  const Base base = two_vertices();
  const std::vector<Vec3> stops{base.positions[0], Vec3(2.5, 2, 0), base.positions[1], base.positions[0]};
  const std::vector<VertexId> ids{0, kNoVertex, 1, 0};
  CorridorOptions o;
  o.radius = 0.8;
  o.join_radius = 3.0;
  o.density = 10.0;
  const CorridorGraph g = corridor_graph(scene, base.graph, base.positions, stops, ids, o);
  EXPECT_EQ(g.walk, (std::vector<VertexId>{0, 2, 1, 0})) << "the refined stop is vertex 2, before the samples";
  EXPECT_EQ(g.positions[2], stops[1]);
  std::size_t joins = 0;
  for (const RoadmapEdge& e : g.graph.edges()) {
    if (e.u < 2 && e.v < 2) continue;
    ++joins;
    EXPECT_TRUE(scene.segment_valid(g.positions[e.u], g.positions[e.v])) << e.u << " - " << e.v;
  }
  EXPECT_GT(joins, 0u);
  EXPECT_GT(g.segments_checked, joins) << "some joins crossed the wall and were refused";
}

TEST(TourCorridor, BadArgumentsAreRefused) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Base base = two_vertices();
  const std::vector<Vec3> stops{base.positions[0], base.positions[1], base.positions[0]};
  CorridorOptions o;
  o.radius = 1.0;
  o.join_radius = 1.5;
  o.density = 1.0;
  EXPECT_THROW((void)corridor_graph(scene, base.graph, base.positions, stops, std::vector<VertexId>{1, 0, 1}, o),
               std::invalid_argument);
  EXPECT_THROW((void)corridor_graph(scene, base.graph, base.positions, stops, std::vector<VertexId>{0, 1}, o),
               std::invalid_argument);
  o.radius = 0.0;
  EXPECT_THROW((void)corridor_graph(scene, base.graph, base.positions, stops, std::vector<VertexId>{0, 1, 0}, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace ispars
