// The GIP solver: exact optima on small instances (against a dynamic-programming reference),
// every tour validated independently, and named errors on bad input.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <queue>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/scene_files/random.hpp"
#include "support/gip_reference.hpp"

namespace ispars::planning {
namespace {

using test::exact_optimum;
using test::random_instance;

TEST(GipSolver, FindsTheExactOptimumOnSmallInstances) {
  for (std::uint64_t seed = 1; seed <= 25; ++seed) {
    const std::size_t pois = 6 + seed % 7;  // 6..12
    const InspectionGraph g = random_instance(seed, 20 + seed % 20, pois);
    const double optimum = exact_optimum(g, pois);
    GipOptions options;
    options.seed = seed;
    options.max_iterations = 300;
    options.budget_seconds = 30;
    const GipResult r = solve_gip(g, options);
    EXPECT_TRUE(r.validation.valid()) << r.validation.problem;
    EXPECT_NEAR(r.tour.cost, optimum, 1e-9 * optimum) << "instance " << seed;
    ASSERT_TRUE(r.lower_bound.has_value());
    EXPECT_LE(*r.lower_bound, optimum + 1e-9);
    EXPECT_EQ(r.tour.covered.size(), pois);
  }
}

TEST(GipSolver, TheSameSeedAndIterationsGiveTheSameTour) {
  const InspectionGraph g = random_instance(77, 60, 12);
  GipOptions options;
  options.seed = 3;
  options.max_iterations = 100;
  options.budget_seconds = 60;
  const GipResult a = solve_gip(g, options);
  const GipResult b = solve_gip(g, options);
  EXPECT_EQ(a.tour.walk, b.tour.walk);
  EXPECT_EQ(a.tour.cost, b.tour.cost);
}

TEST(GipSolver, EveryTourPassesValidationAndTheTraceOnlyImproves) {
  for (std::uint64_t seed = 100; seed < 106; ++seed) {
    const InspectionGraph g = random_instance(seed, 120, 12);
    GipOptions options;
    options.seed = seed;
    options.budget_seconds = 0.3;
    options.threads = 2;
    const GipResult r = solve_gip(g, options);
    EXPECT_TRUE(r.validation.valid()) << r.validation.problem;
    ASSERT_FALSE(r.trace.empty());
    for (std::size_t i = 1; i < r.trace.size(); ++i) EXPECT_LT(r.trace[i].second, r.trace[i - 1].second);
    EXPECT_NEAR(r.trace.back().second, r.tour.cost, 1e-9 * r.tour.cost);
  }
}

TEST(GipSolver, ValidationCatchesBrokenTours) {
  const InspectionGraph g = random_instance(5, 30, 8);
  GipOptions options;
  options.max_iterations = 10;
  const GipResult r = solve_gip(g, options);
  ASSERT_TRUE(r.validation.valid());
  InspectionTour t = r.tour;
  t.cost += 1.0;
  EXPECT_FALSE(validate_tour(g, 0, r.targets, t).cost_matches);
  t = r.tour;
  t.walk.pop_back();
  EXPECT_FALSE(validate_tour(g, 0, r.targets, t).closed);
  t = r.tour;
  t.walk = {0, 0};
  t.cost = 0;
  EXPECT_FALSE(validate_tour(g, 0, r.targets, t).covers_targets);
}

// A warm start: the first chain begins from a given walk, so the result is never costlier, even
// after one iteration; a cold start with the same work is costlier on some instance.
TEST(GipSolver, AWarmStartIsNeverBeatenByTheResult) {
  std::size_t helped = 0;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const InspectionGraph g = random_instance(seed + 200, 150, 14);
    GipOptions long_run;
    long_run.seed = seed;
    long_run.max_iterations = 3000;
    long_run.budget_seconds = 60;
    long_run.lp_bound = false;
    const GipResult good = solve_gip(g, long_run);
    GipOptions short_run = long_run;
    short_run.seed = seed + 1000;
    short_run.max_iterations = 1;
    const GipResult cold = solve_gip(g, short_run);
    short_run.initial_walk = good.tour.walk;
    const GipResult warm = solve_gip(g, short_run);
    EXPECT_TRUE(warm.validation.valid()) << warm.validation.problem;
    EXPECT_LE(warm.tour.cost, good.tour.cost + 1e-9) << "instance " << seed;
    helped += cold.tour.cost > warm.tour.cost + 1e-9;
  }
  EXPECT_GT(helped, 0u) << "one iteration from scratch never did worse: the test shows nothing";
}

TEST(GipSolver, BadInputIsNamed) {
  const auto expect = [](const InspectionGraph& g, const GipOptions& o, const std::string& needle) {
    try {
      (void)solve_gip(g, o);
      ADD_FAILURE() << "accepted: " << needle;
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const std::vector<RoadmapEdge> edges = {{1, 2, 1.0}, {2, 3, 1.0}};
  const InspectionGraph lonely = InspectionGraph::from_edges(4, edges, {{}, {0}, {1}, {2}}, 3);
  expect(lonely, GipOptions{}, "tour: root: the root (vertex 0) has no edges");
  // A root with no edges that sees every target itself: the tour is staying there.
  const InspectionGraph sees_all = InspectionGraph::from_edges(4, edges, {{0}, {0}, {1}, {2}}, 3);
  GipOptions stay;
  stay.targets = std::vector<PoiId>{0};
  const GipResult trivial = solve_gip(sees_all, stay);
  EXPECT_TRUE(trivial.validation.valid()) << trivial.validation.problem;
  EXPECT_EQ(trivial.tour.walk, (std::vector<VertexId>{0}));
  EXPECT_EQ(trivial.tour.cost, 0.0);
  const std::vector<RoadmapEdge> split = {{0, 1, 1.0}, {2, 3, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(4, split, {{}, {0}, {1}, {2}}, 4);
  GipOptions o;
  o.targets.emplace();  // emplace: GCC 12's -Wmaybe-uninitialized misreads an assignment here (unity builds)
  expect(g, o, "tour: targets: the target set is empty");
  o.targets->assign({0, 9});
  expect(g, o, "unknown POI ids (the first: 9");
  GipOptions warm;
  warm.initial_walk = {0, 1, 7, 0};
  expect(g, warm, "tour: initial_walk: vertex 7 is not in the graph (4 vertices)");
  o.targets->assign({0, 1});
  expect(g, o, "1 targets are seen by no vertex reachable from the root (the first: POI 1)");
  o.targets = std::vector<PoiId>{0};
  o.max_iterations = 20;
  const GipResult ok = solve_gip(g, o);
  EXPECT_TRUE(ok.validation.valid());
  EXPECT_EQ(ok.tour.walk, (std::vector<VertexId>{0, 1, 0}));
}

}  // namespace
}  // namespace ispars::planning
