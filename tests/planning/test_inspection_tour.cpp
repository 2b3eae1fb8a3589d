// validate_tour (inspection_tour.hpp): each of its checks on a hand-made graph, alone and
// together, with the first failure named in `problem`.

#include <gtest/gtest.h>

#include <string>

#include "ispars/planning/tour/inspection_tour.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// The triangle 0-1 (1), 1-2 (2), 2-0 (3.5), a parallel 0-1 (0.75) and a pendant 2-3 (1);
// vertex 1 sees POI 0, vertex 3 sees POIs 1 and 2. Four POIs: POI 3 is seen by nobody.
InspectionGraph graph() {
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 2.0}, {2, 0, 3.5}, {1, 0, 0.75}, {2, 3, 1.0}};
  return InspectionGraph::from_edges(4, edges, {{}, {0}, {}, {1, 2}}, 4);
}

InspectionTour tour(std::vector<VertexId> walk, double cost) { return {std::move(walk), cost, {}}; }

using test::mentions;

TEST(InspectionTour, AValidTourPassesEveryCheck) {
  const InspectionGraph g = graph();
  const TourValidation v = validate_tour(g, 0, {0, 1, 2}, tour({0, 1, 2, 3, 2, 0}, 0.75 + 2 + 1 + 1 + 3.5));
  EXPECT_TRUE(v.valid()) << v.problem;
  EXPECT_TRUE(v.closed && v.steps_are_edges && v.covers_targets && v.cost_matches);
  EXPECT_DOUBLE_EQ(v.recomputed_cost, 8.25) << "each step costs its cheapest edge";
  EXPECT_EQ(v.missing_targets, 0u);
  EXPECT_TRUE(v.problem.empty());
}

TEST(InspectionTour, TheRootAloneIsAValidTourForNoTargets) {
  const TourValidation v = validate_tour(graph(), 0, {}, tour({0}, 0.0));
  EXPECT_TRUE(v.valid()) << v.problem;
}

TEST(InspectionTour, StayingPutCostsNothing) {
  const TourValidation v = validate_tour(graph(), 0, {0}, tour({0, 0, 1, 1, 0}, 1.5));
  EXPECT_TRUE(v.valid()) << v.problem;
  EXPECT_DOUBLE_EQ(v.recomputed_cost, 1.5);
}

TEST(InspectionTour, AWalkNotClosedAtTheRootIsRefused) {
  const InspectionGraph g = graph();
  for (const InspectionTour& t : {tour({0, 1}, 0.75), tour({1, 0, 1}, 1.5), tour({}, 0.0)}) {
    const TourValidation v = validate_tour(g, 0, {0}, t);
    EXPECT_FALSE(v.closed);
    EXPECT_FALSE(v.valid());
    EXPECT_TRUE(mentions(v.problem, "start and end at the root 0")) << v.problem;
  }
  // Closed at another root.
  EXPECT_TRUE(validate_tour(g, 1, {0}, tour({1, 0, 1}, 1.5)).valid());
}

TEST(InspectionTour, AStepThatIsNoEdgeOrLeavesTheGraphIsNamed) {
  const InspectionGraph g = graph();
  const TourValidation no_edge = validate_tour(g, 0, {0}, tour({0, 1, 3, 2, 0}, 0.0));
  EXPECT_FALSE(no_edge.steps_are_edges);
  EXPECT_FALSE(no_edge.cost_matches);
  EXPECT_FALSE(no_edge.covers_targets) << "nothing is counted as seen along a broken walk";
  EXPECT_TRUE(no_edge.closed);
  EXPECT_TRUE(mentions(no_edge.problem, "step 2: 1-3 is not an edge")) << no_edge.problem;

  const TourValidation outside = validate_tour(g, 0, {}, tour({0, 7, 0}, 0.0));
  EXPECT_FALSE(outside.steps_are_edges);
  EXPECT_TRUE(mentions(outside.problem, "step 1 names vertex 7 outside the graph")) << outside.problem;
}

TEST(InspectionTour, AStatedCostThatIsNotTheSumIsRefused) {
  const InspectionGraph g = graph();
  const TourValidation wrong = validate_tour(g, 0, {0}, tour({0, 1, 0}, 2.0));  // 1-0 costs 0.75
  EXPECT_TRUE(wrong.steps_are_edges);
  EXPECT_FALSE(wrong.cost_matches);
  EXPECT_TRUE(wrong.covers_targets);
  EXPECT_DOUBLE_EQ(wrong.recomputed_cost, 1.5);
  EXPECT_TRUE(mentions(wrong.problem, "stated cost 2 but the edges sum to 1.5")) << wrong.problem;
  // Within 1e-9 relative the cost matches.
  EXPECT_TRUE(validate_tour(g, 0, {0}, tour({0, 1, 0}, 1.5 * (1 + 1e-10))).cost_matches);
  EXPECT_FALSE(validate_tour(g, 0, {0}, tour({0, 1, 0}, 1.5 * (1 + 1e-8))).cost_matches);
}

TEST(InspectionTour, MissingTargetsAreCounted) {
  const InspectionGraph g = graph();
  // The walk 0-1-0 sees POI 0 only; POI 3 is seen by nobody and POI 9 is not in the graph.
  const TourValidation v = validate_tour(g, 0, {0, 1, 2, 3, 9}, tour({0, 1, 0}, 1.5));
  EXPECT_TRUE(v.steps_are_edges);
  EXPECT_TRUE(v.cost_matches);
  EXPECT_FALSE(v.covers_targets);
  EXPECT_EQ(v.missing_targets, 4u);
  EXPECT_TRUE(mentions(v.problem, "4 targets are not seen")) << v.problem;
}

TEST(InspectionTour, TheProblemIsTheFirstFailure) {
  // Not closed, and a wrong cost: the problem names the first.
  const TourValidation v = validate_tour(graph(), 0, {3}, tour({0, 1}, 9.0));
  EXPECT_FALSE(v.closed);
  EXPECT_FALSE(v.cost_matches);
  EXPECT_FALSE(v.covers_targets);
  EXPECT_TRUE(mentions(v.problem, "root")) << v.problem;
}

}  // namespace
}  // namespace ispars::planning
