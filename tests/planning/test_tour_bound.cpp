// The LP tour bound (tour_bound.hpp) and its cut separation (cut_separation.hpp): never above
// the exact optimum, on instances built to be hard for it; max-flow cuts by hand; stopping.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <numeric>

#include "ispars/planning/tour/cut_separation.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_bound.hpp"
#include "support/gip_reference.hpp"

namespace ispars::planning {
namespace {

std::vector<PoiId> all_pois(std::size_t pois) {
  std::vector<PoiId> t(pois);
  std::iota(t.begin(), t.end(), 0);
  return t;
}

TEST(TourBound, NeverAboveTheExactOptimumAndSolvedToTheEnd) {
  // Trees (every tour walks each used edge twice), sparse and denser graphs, up to 12 POIs.
  double ratio_sum = 0.0;
  int instances = 0;
  for (std::uint64_t seed = 1; seed <= 60; ++seed) {
    const std::size_t pois = 4 + seed % 9;
    const std::size_t nearest = seed % 4;  // 0: a path graph
    const InspectionGraph g = test::random_instance(seed, 8 + seed % 30, pois, nearest);
    const double optimum = test::exact_optimum(g, pois);
    TourBoundOptions options;
    options.targets = all_pois(pois);
    options.budget_seconds = 30;
    const TourBoundResult r = lp_tour_bound(g, options);
    ASSERT_TRUE(r.skipped.empty()) << r.skipped;
    EXPECT_TRUE(r.complete) << "instance " << seed;
    EXPECT_LE(r.bound, optimum * (1.0 + 1e-9)) << "instance " << seed << ": the bound claims more than is true";
    EXPECT_GT(r.bound, 0.0) << "instance " << seed;
    ratio_sum += r.bound / optimum;
    ++instances;
    // The trace only rises and ends at the bound.
    for (std::size_t i = 1; i < r.trace.size(); ++i) EXPECT_GT(r.trace[i].second, r.trace[i - 1].second);
    if (!r.trace.empty()) {
      EXPECT_EQ(r.trace.back().second, r.bound);
    }
  }
  // Not a promise of strength per instance, but a bound far below the optimum is useless.
  EXPECT_GT(ratio_sum / instances, 0.8);
}

TEST(TourBound, ThroughTheSolverBoundLeqOptimumLeqTour) {
  for (std::uint64_t seed = 100; seed < 120; ++seed) {
    const std::size_t pois = 6 + seed % 7;
    const InspectionGraph g = test::random_instance(seed, 15 + seed % 25, pois);
    const double optimum = test::exact_optimum(g, pois);
    GipOptions options;
    options.seed = seed;
    options.max_iterations = 200;
    options.budget_seconds = 30;
    const GipResult r = solve_gip(g, options);
    ASSERT_TRUE(r.lower_bound.has_value());
    EXPECT_LE(*r.lower_bound, optimum * (1.0 + 1e-9)) << "instance " << seed;
    EXPECT_LE(optimum, r.tour.cost * (1.0 + 1e-9));
    ASSERT_FALSE(r.bound_trace.empty());
    EXPECT_EQ(r.bound_trace.back().second, *r.lower_bound);
  }
}

TEST(TourBound, TargetsTheRootSeesNeedNoTour) {
  // A star: the root sees POI 0, a leaf at distance 2 sees POI 1; the optimum is 4, and POI 0
  // alone needs nothing.
  const std::vector<RoadmapEdge> edges{{0, 1, 2.0}, {0, 2, 5.0}};
  const InspectionGraph g = InspectionGraph::from_edges(3, edges, {{0}, {1}, {}}, 2);
  TourBoundOptions options;
  options.targets = {0};
  EXPECT_EQ(lp_tour_bound(g, options).bound, 0.0);
  EXPECT_TRUE(lp_tour_bound(g, options).complete);
  options.targets = {0, 1};
  const TourBoundResult r = lp_tour_bound(g, options);
  EXPECT_TRUE(r.complete);
  EXPECT_NEAR(r.bound, 4.0, 1e-6);
  EXPECT_LE(r.bound, 4.0);
}

TEST(TourBound, StopsWhenAskedAndWhenTheGraphIsTooLarge) {
  const InspectionGraph g = test::random_instance(7, 400, 60, 6);
  TourBoundOptions options;
  options.targets = all_pois(60);
  options.should_stop = [] { return true; };
  const auto t0 = std::chrono::steady_clock::now();
  const TourBoundResult stopped = lp_tour_bound(g, options);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.5);
  EXPECT_FALSE(stopped.complete);
  options.should_stop = nullptr;
  options.max_edges = 10;
  const TourBoundResult skipped = lp_tour_bound(g, options);
  EXPECT_NE(skipped.skipped.find("more than the LP's limit of 10"), std::string::npos) << skipped.skipped;
  EXPECT_FALSE(skipped.complete);
  EXPECT_EQ(skipped.bound, 0.0);
}

TEST(TourBound, TheSizeCapHoldsDropsIdleCutsAndNeverClaimsMore) {
  // Under a cap a few cuts wide the LP drops the cuts that do not bind and finds them again; its
  // nonzeros never pass the cap and its bound stays proven (<= the optimum, <= the uncapped bound).
  int dropped_somewhere = 0, solved_after_drops = 0;
  for (std::uint64_t seed = 1; seed <= 24; ++seed) {
    const std::size_t pois = 6 + seed % 7;
    const InspectionGraph g = test::random_instance(seed, 20 + seed % 20, pois, 3);
    const double optimum = test::exact_optimum(g, pois);
    TourBoundOptions options;
    options.targets = all_pois(pois);
    options.budget_seconds = 30;
    const TourBoundResult free = lp_tour_bound(g, options);
    options.max_cut_nonzeros = 4 * g.edge_count();
    const TourBoundResult capped = lp_tour_bound(g, options);
    EXPECT_LE(capped.peak_nonzeros, options.max_cut_nonzeros) << "instance " << seed;
    EXPECT_LE(capped.bound, optimum * (1.0 + 1e-9)) << "instance " << seed;
    EXPECT_LE(capped.bound, free.bound * (1.0 + 1e-6)) << "instance " << seed;
    EXPECT_FALSE(capped.complete && capped.capped) << "instance " << seed;
    if (capped.complete) {
      EXPECT_NEAR(capped.bound, free.bound, 1e-6 * free.bound) << "instance " << seed << ": the same LP optimum";
    }
    dropped_somewhere += capped.dropped > 0 ? 1 : 0;
    solved_after_drops += capped.dropped > 0 && capped.complete ? 1 : 0;
  }
  EXPECT_GT(dropped_somewhere, 0) << "no instance reached the cap: the test does not test it";
  EXPECT_GT(solved_after_drops, 0) << "no capped LP reached its optimum over all cuts";
}

TEST(CutSeparation, MaxFlowAndBothCutsOnAPath) {
  // root 0 - 1 - 2 - 3, capacities 1.5, 0.5, 2; the group is {3}.
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}, {2, 3, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{}, {}, {}, {0}}, 1);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0});
  ASSERT_EQ(cg.groups.size(), 1u);
  MaxFlow flow(cg);
  const double x[] = {1.5, 0.5, 2.0};
  flow.set_capacities(x);
  EXPECT_NEAR(flow.max_flow_to(cg.groups[0], 2.0), 0.5, 1e-12);
  EXPECT_EQ(flow.source_side(), (std::vector<char>{1, 1, 0, 0}));           // the cut 1-2
  EXPECT_EQ(flow.sink_side_complement(), (std::vector<char>{1, 1, 0, 0}));  // the same one here
  // With the middle edge at 3 the flow reaches the limit and stops there.
  const double wide[] = {2.5, 3.0, 2.5};
  flow.set_capacities(wide);
  EXPECT_NEAR(flow.max_flow_to(cg.groups[0], 2.0), 2.0, 1e-12);
}

TEST(CutSeparation, GroupsAreLocalDeduplicatedAndSkipWhatTheRootSees) {
  // Two components; POIs 0 and 1 seen by the same vertices, POI 2 by the root, POI 3 elsewhere.
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}, {3, 4, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(5, edges, {{2}, {0, 1}, {0, 1}, {3}, {3}}, 4);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0, 1, 2, 3});
  EXPECT_EQ(cg.vertex_count, 3u);
  EXPECT_EQ(cg.edges.size(), 2u);
  ASSERT_EQ(cg.groups.size(), 1u) << "POIs 0 and 1 share a group; 2 is seen at the root; 3 is elsewhere";
  EXPECT_EQ(cg.groups[0], (std::vector<std::uint32_t>{1, 2}));
}

}  // namespace
}  // namespace ispars::planning
