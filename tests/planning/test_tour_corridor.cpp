// Corridor densification (tour_corridor.hpp): the tube's samples are uniform at the asked density
// and lie within r of the path; the base graph keeps its ids and edges; the flown path is a walk
// of the new graph; every new edge is within the join radius and collision-free; the same seed
// gives the same graph. Given samples and the build's stream drawn again: exactly those a brute-force
// distance test puts in the tube, in their order, without the base's own positions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "ispars/planning/tour/tour_corridor.hpp"
#include "ispars/scene_files/random.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
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

// What the found sources must keep: in the tube (brute force), in the box, valid, not a base
// position; the first `cap`, in order.
std::vector<Vec3> expected_found(const Scene& scene, const std::vector<Vec3>& candidates,
                                 const std::vector<Vec3>& stops, const std::vector<Vec3>& base, double r,
                                 std::size_t cap) {
  std::vector<Vec3> out;
  for (const Vec3& q : candidates) {
    if (out.size() >= cap) break;
    if (distance_to_path(q, stops) > r || !scene.config().bounds.contains(q) || !scene.point_valid(q)) continue;
    if (std::find(base.begin(), base.end(), q) != base.end()) continue;
    out.push_back(q);
  }
  return out;
}

TEST(TourCorridor, GivenSamplesAndTheStreamKeepExactlyThoseInTheTube) {
  const Scene scene = test::open_scene(1.0, 1.5, /*wall=*/true);
  scene_files::Rng rng(7);
  // A base graph: the root and 20 random vertices, a path through some of them (long diagonal
  // segments included), then candidates: random ones, ones near the path, and the base's own.
  std::vector<Vec3> positions{Vec3(0, 0, 0)};
  for (int i = 0; i < 20; ++i) positions.push_back(rng.uniform_in(scene.config().bounds));
  const InspectionGraph graph =
      InspectionGraph::from_edges(positions.size(), {}, std::vector<std::vector<PoiId>>(positions.size()), 3);
  const std::vector<Vec3> stops{positions[0], positions[3], positions[7], Vec3(-45, 45, -45), positions[0]};
  const std::vector<VertexId> ids{0, 3, 7, kNoVertex, 0};
  std::vector<Vec3> candidates;
  for (int i = 0; i < 3000; ++i) candidates.push_back(rng.uniform_in(scene.config().bounds));
  for (int i = 0; i < 2000; ++i) {
    const std::size_t k = i % 4;
    const double t = rng.uniform01();
    candidates.push_back(stops[k] + t * (stops[k + 1] - stops[k]) + rng.uniform(-4.0, 4.0) * rng.unit_vector());
  }
  candidates.insert(candidates.end(), positions.begin(), positions.end());
  CorridorOptions o;
  o.radius = 2.5;
  o.join_radius = 3.0;
  o.source = CorridorSource::samples;
  o.samples = candidates;
  o.max_samples = 100'000;
  std::vector<Vec3> base = positions;
  base.push_back(stops[3]);  // the stop off the graph becomes vertex 21
  const std::vector<Vec3> wanted = expected_found(scene, candidates, stops, base, o.radius, o.max_samples);
  ASSERT_GT(wanted.size(), 500u);
  const CorridorGraph g = corridor_graph(scene, graph, positions, stops, ids, o);
  ASSERT_EQ(g.samples, wanted.size());
  EXPECT_EQ(std::vector<Vec3>(g.positions.begin() + 22, g.positions.end()), wanted);
  // The cap keeps the first ones.
  o.max_samples = 40;
  const CorridorGraph capped = corridor_graph(scene, graph, positions, stops, ids, o);
  EXPECT_EQ(std::vector<Vec3>(capped.positions.begin() + 22, capped.positions.end()),
            std::vector<Vec3>(wanted.begin(), wanted.begin() + 40));
  // The stream: Rng(stream_seed) drawn stream_count times in the scene's bounds, as builders draw.
  o.max_samples = 100'000;
  o.source = CorridorSource::stream;
  o.stream_seed = 11;
  o.stream_count = 40'000;
  scene_files::Rng stream(11);
  std::vector<Vec3> drawn;
  for (int i = 0; i < 40'000; ++i) drawn.push_back(stream.uniform_in(scene.config().bounds));
  const std::vector<Vec3> from_stream = expected_found(scene, drawn, stops, base, o.radius, o.max_samples);
  ASSERT_GT(from_stream.size(), 50u);
  const CorridorGraph s = corridor_graph(scene, graph, positions, stops, ids, o);
  EXPECT_EQ(std::vector<Vec3>(s.positions.begin() + 22, s.positions.end()), from_stream);
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
}  // namespace ispars::planning
