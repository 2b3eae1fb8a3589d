// Shortcut tours: straight segments replace stretches of a roadmap tour, never across what the
// collision checker refuses, never dropping the last stop that sees a target, never longer.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

// Refuses every segment that passes within `radius` of `centre` (a ball obstacle).
SegmentValid avoiding(const Vec3& centre, double radius) {
  return [centre, radius](const Vec3& a, const Vec3& b) {
    const Vec3 d = b - a;
    const double len2 = d.squaredNorm();
    const double s = len2 > 0 ? std::clamp((centre - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    return (a + s * d - centre).norm() > radius;
  };
}

// A staircase 0 -> 1 -> ... -> n-1 along x and y alternately, and straight back; vertex k sees
// POI k when k is in `viewpoints`.
struct Staircase {
  std::vector<Vec3> positions;
  InspectionGraph graph;
};

Staircase staircase(std::size_t n, const std::vector<std::size_t>& viewpoints) {
  Staircase s;
  std::vector<RoadmapEdge> edges;
  std::vector<std::vector<PoiId>> visible(n);
  for (std::size_t k = 0; k < n; ++k) {
    s.positions.emplace_back(static_cast<double>((k + 1) / 2), static_cast<double>(k / 2), 0.0);
    if (k > 0) edges.push_back({static_cast<VertexId>(k - 1), static_cast<VertexId>(k), 1.0});
  }
  for (std::size_t i = 0; i < viewpoints.size(); ++i) visible[viewpoints[i]] = {static_cast<PoiId>(i)};
  s.graph = InspectionGraph::from_edges(n, edges, std::move(visible), viewpoints.size());
  return s;
}

InspectionTour out_and_back(std::size_t n) {
  InspectionTour t;
  for (std::size_t k = 0; k < n; ++k) t.walk.push_back(static_cast<VertexId>(k));
  for (std::size_t k = n - 1; k-- > 0;) t.walk.push_back(static_cast<VertexId>(k));
  t.cost = 2.0 * static_cast<double>(n - 1);
  return t;
}

TEST(TourShortcut, InFreeSpaceAStaircaseBecomesStraightAndKeepsItsViewpoints) {
  const Staircase s = staircase(21, {20});  // the far end sees the only target
  const std::vector<PoiId> targets{0};
  const auto free = [](const Vec3&, const Vec3&) { return true; };
  const ShortcutTour t = shortcut_tour(s.graph, s.positions, targets, out_and_back(21), free);
  EXPECT_EQ(t.stops, (std::vector<VertexId>{0, 20, 0}));
  EXPECT_NEAR(t.cost, 2.0 * s.positions[20].norm(), 1e-12);  // straight there and back
  EXPECT_TRUE(check_shortcut_tour(s.graph, s.positions, 0, targets, t, free).valid());
}

TEST(TourShortcut, AViewpointSeeingATargetNoOtherStopSeesIsKept) {
  const Staircase s = staircase(21, {7, 13, 20});
  const std::vector<PoiId> targets{0, 1, 2};
  const auto free = [](const Vec3&, const Vec3&) { return true; };
  const ShortcutTour t = shortcut_tour(s.graph, s.positions, targets, out_and_back(21), free);
  for (const VertexId v : {7u, 13u, 20u}) {
    ASSERT_NE(std::find(t.stops.begin(), t.stops.end(), v), t.stops.end()) << "viewpoint " << v;
  }
  // A target seen only by vertex 7 and no other: dropping 7 would be caught by the check.
  ShortcutTour broken = t;
  broken.stops.erase(std::find(broken.stops.begin(), broken.stops.end(), 7u));
  EXPECT_FALSE(check_shortcut_tour(s.graph, s.positions, 0, targets, broken, free).covers_targets);
}

TEST(TourShortcut, NoSegmentCrossesWhatTheCheckerRefuses) {
  const Staircase s = staircase(21, {20});
  const std::vector<PoiId> targets{0};
  const SegmentValid blocked = avoiding({5.667, 5.333, 0.0}, 0.3);  // across the diagonal, clear of the stairs
  const ShortcutTour t = shortcut_tour(s.graph, s.positions, targets, out_and_back(21), blocked);
  const ShortcutValidation v = check_shortcut_tour(s.graph, s.positions, 0, targets, t, blocked);
  EXPECT_TRUE(v.valid()) << v.problem;
  EXPECT_GT(t.stops.size(), 3u);  // the straight line is blocked
  EXPECT_LT(t.cost, 40.0);        // and still shorter than the stairs
  const auto free = [](const Vec3&, const Vec3&) { return true; };
  EXPECT_LT(shortcut_tour(s.graph, s.positions, targets, out_and_back(21), free).cost, t.cost);
}

TEST(TourShortcut, SolvedToursShortenDeterministicallyAndStayValid) {
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    scene_files::Rng rng(seed);
    const std::size_t n = 150, pois = 25;
    std::vector<Vec3> at;
    for (std::size_t i = 0; i < n; ++i) at.emplace_back(rng.uniform01(), rng.uniform01(), rng.uniform01());
    std::vector<RoadmapEdge> edges;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const double d = (at[i] - at[j]).norm();
        if (d < 0.22 || j == i + 1) edges.push_back({static_cast<VertexId>(i), static_cast<VertexId>(j), d});
      }
    }
    std::vector<std::vector<PoiId>> visible(n);
    for (std::size_t i = 1; i < n; ++i) {
      if (rng.uniform01() < 0.5) visible[i] = {static_cast<PoiId>(rng.uniform01() * pois)};
    }
    for (PoiId p = 0; p < pois; ++p) visible[1 + p].push_back(p);  // every POI seen
    for (auto& v : visible) std::sort(v.begin(), v.end()), v.erase(std::unique(v.begin(), v.end()), v.end());
    const InspectionGraph g = InspectionGraph::from_edges(n, edges, std::move(visible), pois);
    GipOptions o;
    o.seed = seed;
    o.max_iterations = 100;
    o.lp_bound = false;
    const GipResult r = solve_gip(g, o);
    const SegmentValid ball = avoiding({0.5, 0.5, 0.5}, 0.25);
    const ShortcutTour t = shortcut_tour(g, at, r.targets, r.tour, ball);
    const ShortcutValidation v = check_shortcut_tour(g, at, 0, r.targets, t, ball);
    EXPECT_TRUE(v.valid()) << "instance " << seed << ": " << v.problem;
    EXPECT_LE(t.cost, r.tour.cost * (1 + 1e-12)) << "instance " << seed;
    EXPECT_EQ(shortcut_tour(g, at, r.targets, r.tour, ball).stops, t.stops) << "instance " << seed;
    std::atomic<bool> stop{true};  // stopped from the start: the walk as it was, still sound
    ShortcutOptions stopped;
    stopped.stop = &stop;
    const ShortcutTour s = shortcut_tour(g, at, r.targets, r.tour, ball, stopped);
    EXPECT_TRUE(s.stopped);
    EXPECT_NEAR(s.cost, r.tour.cost, 1e-9 * r.tour.cost);
    EXPECT_TRUE(check_shortcut_tour(g, at, 0, r.targets, s, ball).valid());
  }
}

TEST(TourShortcut, ABudgetEndsShorteningWithAValidPathWithinAWindowOfChecks) {
  // A slow collision checker (2 ms a segment) on a long staircase: with a 20 ms budget the
  // shortening stops after a handful of stops, leaving a path shortened in part and still sound.
  const Staircase s = staircase(401, {400});
  const std::vector<PoiId> targets{0};
  const auto slow = [](const Vec3&, const Vec3&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return false;  // nothing straight: every stop tries its whole window
  };
  ShortcutOptions budgeted;
  budgeted.budget_seconds = 0.02;
  const auto t0 = std::chrono::steady_clock::now();
  const ShortcutTour t = shortcut_tour(s.graph, s.positions, targets, out_and_back(401), slow, budgeted);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(t.stopped);
  // At most one stop's window past the budget (without it: ~800 stops x 48 checks, ~77 s).
  EXPECT_LE(t.segments_checked, 20u / 2 + 2 * budgeted.window);
  EXPECT_LT(seconds, 1.0);
  const auto free = [](const Vec3&, const Vec3&) { return true; };
  EXPECT_TRUE(check_shortcut_tour(s.graph, s.positions, 0, targets, t, free).valid());
}

}  // namespace
}  // namespace ispars::planning
