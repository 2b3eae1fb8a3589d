// CutGraph and MaxFlow (cut_separation.hpp) on tiny graphs whose flows and cuts are known by
// hand. (test_tour_bound.cpp has the first two: the cut 1-2 on a path, and group deduplication.)

#include <gtest/gtest.h>

#include "ispars/planning/tour/cut_separation.hpp"

namespace ispars::planning {
namespace {

using Local = std::vector<std::uint32_t>;

TEST(CutGraph, ComponentOfANonZeroRootGetsLocalIdsInGlobalOrder) {
  // Component {1, 2, 4} (root 2) and component {0, 3}; a self-loop at 4.
  const std::vector<RoadmapEdge> edges{{0, 3, 1.0}, {4, 2, 2.5}, {1, 2, 0.5}, {4, 4, 0.0}};
  const InspectionGraph g = InspectionGraph::from_edges(5, edges, {{0}, {1}, {}, {0}, {1, 2}}, 4);
  const CutGraph cg = CutGraph::of_component(g, 2, std::vector<PoiId>{0, 1, 2, 3});
  EXPECT_EQ(cg.vertex_count, 3u);
  EXPECT_EQ(cg.root, 1u);  // global 2 is the second of 1, 2, 4
  ASSERT_EQ(cg.edges.size(), 2u) << "the other component's edge and the self-loop are left out";
  EXPECT_EQ(cg.edges[0], (std::pair<std::uint32_t, std::uint32_t>{2, 1}));  // 4-2, as given
  EXPECT_EQ(cg.edges[1], (std::pair<std::uint32_t, std::uint32_t>{0, 1}));  // 1-2
  EXPECT_EQ(cg.costs, (std::vector<double>{2.5, 0.5}));
  // POI 0 is seen only outside the component and POI 3 by nobody: no group. POI 1 by local 0
  // and 2, POI 2 by local 2. Sorted.
  EXPECT_EQ(cg.groups, (std::vector<Local>{{0, 2}, {2}}));
}

TEST(CutGraph, OnlyTheGivenTargetsMakeGroups) {
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(3, edges, {{}, {0}, {1}}, 2);
  EXPECT_EQ(CutGraph::of_component(g, 0, std::vector<PoiId>{1}).groups, (std::vector<Local>{{2}}));
  EXPECT_TRUE(CutGraph::of_component(g, 0, std::vector<PoiId>{}).groups.empty());
}

// root 0 - 1 - 2 - 3 with capacities 0.5, 2, 0.5: two minimum cuts, 0-1 and 2-3. The source side
// stops at the first, the complement of the sink side at the last.
TEST(MaxFlow, SourceSideAndSinkSideComplementFindTheCutsNearestEachEnd) {
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}, {2, 3, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{}, {}, {}, {0}}, 1);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0});
  MaxFlow flow(cg);
  const double x[] = {0.5, 2.0, 0.5};
  flow.set_capacities(x);
  EXPECT_NEAR(flow.max_flow_to(cg.groups.at(0), 2.0), 0.5, 1e-12);
  EXPECT_EQ(flow.source_side(), (std::vector<char>{1, 0, 0, 0}));
  EXPECT_EQ(flow.sink_side_complement(), (std::vector<char>{1, 1, 1, 0}));
}

// The diamond root 0 -> {1, 2} -> 3 with x = 0.3 on the 1 side and 0.4 on the 2 side: the flow
// to {3} is 0.7 < 1, so the constraint x(delta(S)) >= 1 is violated for the cut the flow finds.
TEST(MaxFlow, ViolatedCutOnADiamondIsTheMinimumCut) {
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {0, 2, 1.0}, {1, 3, 1.0}, {2, 3, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{}, {}, {}, {0}}, 1);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0});
  MaxFlow flow(cg);
  const double x[] = {0.3, 0.9, 0.6, 0.4};  // bottlenecks: 0-1 (0.3) and 2-3 (0.4)
  flow.set_capacities(x);
  EXPECT_NEAR(flow.max_flow_to(cg.groups.at(0), 1.0), 0.7, 1e-12);
  const std::vector<char> s = flow.source_side();
  EXPECT_EQ(s, (std::vector<char>{1, 0, 1, 0}));
  // The edges leaving S carry exactly the flow: the cut is minimum, and violated.
  double crossing = 0.0;
  for (std::size_t e = 0; e < cg.edges.size(); ++e) {
    if (s[cg.edges[e].first] != s[cg.edges[e].second]) crossing += x[e];
  }
  EXPECT_NEAR(crossing, 0.7, 1e-12);
  EXPECT_LT(crossing, 1.0);
}

TEST(MaxFlow, EdgesCarryFlowBothWays) {
  // Edges listed toward the root: 1-0 and 2-1; the flow runs from 0 to 2 against their order.
  const std::vector<RoadmapEdge> edges{{1, 0, 1.0}, {2, 1, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(3, edges, {{}, {}, {0}}, 1);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0});
  MaxFlow flow(cg);
  const double x[] = {0.75, 1.0};
  flow.set_capacities(x);
  EXPECT_NEAR(flow.max_flow_to(cg.groups.at(0), 5.0), 0.75, 1e-12);
}

TEST(MaxFlow, GroupMembersShareTheSinkAndEachFlowStartsAfresh) {
  // The star 0-1 (0.4), 0-2 (0.7), 0-3 (0.2); POI 0 seen at 1 and 2, POI 1 at 3.
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {0, 2, 1.0}, {0, 3, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(4, edges, {{}, {0}, {0}, {1}}, 2);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0, 1});
  ASSERT_EQ(cg.groups, (std::vector<Local>{{1, 2}, {3}}));
  MaxFlow flow(cg);
  const double x[] = {0.4, 0.7, 0.2};
  flow.set_capacities(x);
  EXPECT_NEAR(flow.max_flow_to(cg.groups[0], 5.0), 1.1, 1e-12);
  EXPECT_NEAR(flow.max_flow_to(cg.groups[0], 5.0), 1.1, 1e-12) << "the residuals are reset";
  EXPECT_NEAR(flow.max_flow_to(cg.groups[1], 5.0), 0.2, 1e-12);
  EXPECT_EQ(flow.source_side(), (std::vector<char>{1, 1, 1, 0}));
  EXPECT_NEAR(flow.max_flow_to(cg.groups[0], 0.5), 0.5, 1e-12) << "stops at the limit";
}

TEST(MaxFlow, EdgesAtZeroAreNotInTheSupport) {
  const std::vector<RoadmapEdge> edges{{0, 1, 1.0}, {1, 2, 1.0}};
  const InspectionGraph g = InspectionGraph::from_edges(3, edges, {{}, {}, {0}}, 1);
  const CutGraph cg = CutGraph::of_component(g, 0, std::vector<PoiId>{0});
  MaxFlow flow(cg);
  const double x[] = {1.0, 1e-12};
  flow.set_capacities(x);
  EXPECT_EQ(flow.max_flow_to(cg.groups.at(0), 1.0), 0.0);
  EXPECT_EQ(flow.source_side(), (std::vector<char>{1, 1, 0}));
  EXPECT_EQ(flow.sink_side_complement(), (std::vector<char>{1, 1, 0}));
  // New capacities replace the old ones.
  const double full[] = {1.0, 1.0};
  flow.set_capacities(full);
  EXPECT_NEAR(flow.max_flow_to(cg.groups.at(0), 1.0), 1.0, 1e-12);
}

}  // namespace
}  // namespace ispars::planning
