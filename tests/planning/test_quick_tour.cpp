// nearest_viewpoint_tour (quick_tour.hpp): the nearest-unseen-viewpoint walk on line graphs and
// small trees, where its walk is known by hand; its cost, its covered targets, and `stop`.

#include <gtest/gtest.h>

#include <atomic>

#include "ispars/planning/tour/quick_tour.hpp"

namespace ispars::planning {
namespace {

// The line 0 - 1 - ... - n-1 with the given edge costs (costs.size() == n - 1).
InspectionGraph line(const std::vector<double>& costs, std::vector<std::vector<PoiId>> visible, std::size_t pois) {
  std::vector<RoadmapEdge> edges;
  for (std::size_t i = 0; i < costs.size(); ++i) {
    edges.push_back({static_cast<VertexId>(i), static_cast<VertexId>(i + 1), costs[i]});
  }
  return InspectionGraph::from_edges(costs.size() + 1, edges, std::move(visible), pois);
}

TEST(QuickTour, WalksOutToTheFarthestViewpointAndHome) {
  const InspectionGraph g = line({1, 2, 1, 0.5}, {{}, {}, {0}, {}, {1}}, 2);
  const std::vector<PoiId> targets{1, 0};
  const auto tour = nearest_viewpoint_tour(g, 0, targets, nullptr);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->walk, (std::vector<VertexId>{0, 1, 2, 3, 4, 3, 2, 1, 0}));
  EXPECT_DOUBLE_EQ(tour->cost, 9.0);
  EXPECT_EQ(tour->covered, (std::vector<PoiId>{0, 1}));
  EXPECT_TRUE(validate_tour(g, 0, targets, *tour).valid()) << validate_tour(g, 0, targets, *tour).problem;
}

TEST(QuickTour, TakesTheNearestUnseenViewpointFirst) {
  // Root 2 in the middle: POI 0 at vertex 0 (2 away), POI 1 at vertex 3 (1 away). Right first,
  // then across to the left end, then home.
  const InspectionGraph g = line({1, 1, 1, 1}, {{0}, {}, {}, {1}, {}}, 2);
  const auto tour = nearest_viewpoint_tour(g, 2, {0, 1}, nullptr);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->walk, (std::vector<VertexId>{2, 3, 2, 1, 0, 1, 2}));
  EXPECT_DOUBLE_EQ(tour->cost, 6.0);
  // With the right-hand edge dearer, the left end is nearer: left first.
  const InspectionGraph dear = line({1, 1, 2.5, 1}, {{0}, {}, {}, {1}, {}}, 2);
  const auto other = nearest_viewpoint_tour(dear, 2, {0, 1}, nullptr);
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(other->walk, (std::vector<VertexId>{2, 1, 0, 1, 2, 3, 2}));
  EXPECT_DOUBLE_EQ(other->cost, 9.0);
}

TEST(QuickTour, AnotherViewpointOfASeenTargetIsNotVisited) {
  // A tree: root 0, branch 0-1-2 and branch 0-3. POI 0 at 1 and at 3; POI 1 at 2. The walk goes
  // to 1 (nearest, sees POI 0), on to 2 (POI 1), and home: branch 3 is never entered.
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}, {0, 3, 1.5}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{}, {0}, {1}, {0}}, 2);
  const auto tour = nearest_viewpoint_tour(g, 0, {0, 1}, nullptr);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->walk, (std::vector<VertexId>{0, 1, 2, 1, 0}));
  EXPECT_DOUBLE_EQ(tour->cost, 4.0);
}

TEST(QuickTour, TargetsSeenAtTheRootOrNoneGiveTheEmptyTour) {
  const InspectionGraph g = line({1, 1}, {{0, 1}, {}, {2}}, 3);
  for (const std::vector<PoiId>& targets : {std::vector<PoiId>{}, std::vector<PoiId>{1, 0, 1}}) {
    const auto tour = nearest_viewpoint_tour(g, 0, targets, nullptr);
    ASSERT_TRUE(tour.has_value());
    EXPECT_EQ(tour->walk, std::vector<VertexId>{0});
    EXPECT_EQ(tour->cost, 0.0);
    EXPECT_TRUE(validate_tour(g, 0, targets, *tour).valid());
  }
  // Duplicate targets are covered once, ascending.
  const auto tour = nearest_viewpoint_tour(g, 0, {2, 0, 2}, nullptr);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->covered, (std::vector<PoiId>{0, 2}));
  EXPECT_EQ(tour->walk, (std::vector<VertexId>{0, 1, 2, 1, 0}));
}

TEST(QuickTour, CostCountsTheCheapestOfParallelEdges) {
  const std::vector<RoadmapEdge> edges{{0, 1, 3.0}, {1, 0, 1.25}, {0, 1, 2.0}};
  const InspectionGraph g = InspectionGraph::from_edges(2, edges, {{}, {0}}, 1);
  const auto tour = nearest_viewpoint_tour(g, 0, {0}, nullptr);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->walk, (std::vector<VertexId>{0, 1, 0}));
  EXPECT_DOUBLE_EQ(tour->cost, 2.5);
}

TEST(QuickTour, AStopSetBeforehandGivesNothingOnALargeGraph) {
  // 20,000 vertices in a line, the only target at the far end: the search checks `stop` every
  // 4096 settled vertices, so it sees it long before the end.
  const std::size_t n = 20'000;
  std::vector<std::vector<PoiId>> visible(n);
  visible.back() = {0};
  const InspectionGraph g = line(std::vector<double>(n - 1, 1.0), std::move(visible), 1);
  std::atomic<bool> stop{true};
  EXPECT_FALSE(nearest_viewpoint_tour(g, 0, {0}, &stop).has_value());
  stop = false;
  const auto tour = nearest_viewpoint_tour(g, 0, {0}, &stop);
  ASSERT_TRUE(tour.has_value());
  EXPECT_EQ(tour->walk.size(), 2 * n - 1);
  EXPECT_DOUBLE_EQ(tour->cost, 2.0 * static_cast<double>(n - 1));
}

}  // namespace
}  // namespace ispars::planning
