// The dense shortcut of SPARS (Alg. 1, lines 24-26; spars_spanner.cpp) on hand-placed samples:
// root 0 and guard 1 at (5, 0, 0), joined only through bridge 2 at (2.5, 1.5, 0), so the
// interfaces 2|0 and 2|1 exist and 0, 1 are not adjacent. A sample q with rep 2 that supports
// 2|0 compares (|2 - 0| + |2 - 1|) / 2 with t times its dense route to a support of 2|1.
// The records and admissions are the builder's public account of each shortcut.

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/planning/builders/spars_builder.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

using test::valid_at;

// SPARS of Alg. 1 (no inspection test, dense shortcut on, no stretch rules).
SparsRules shortcut_rules() { return SparsRules::for_variant(SparsVariant::alg1, false); }

const double kBridgeLength = std::sqrt(2.5 * 2.5 + 1.5 * 1.5);  // |bridge - root| = |bridge - guard|

// Root, guard and bridge (sparse 0, 1, 2; dense 0, 1, 2), with no dense edge between them.
void place_bridge(SparsBuilder& b) {
  b.step(valid_at(Vec3(5, 0, 0)));
  b.step(valid_at(Vec3(2.5, 1.5, 0)));
  ASSERT_EQ(b.roadmap().vertex_count(), 3u);
  ASSERT_EQ(b.admissions().guard, 1u);
  ASSERT_EQ(b.admissions().bridge, 1u);
  ASSERT_TRUE(b.roadmap().has_edge(2, 0));
  ASSERT_TRUE(b.roadmap().has_edge(2, 1));
  ASSERT_FALSE(b.roadmap().has_edge(0, 1));
  ASSERT_EQ(b.dense()->edge_count(), 0u);
}

TEST(SparsShortcut, ShortDenseRouteBetweenInterfacesAddsTheDirectEdge) {
  const Scene scene = test::open_scene(2.6, 3.0);
  SparsBuilder b(scene, BuildOptions{}, shortcut_rules());
  place_bridge(b);
  // x (dense 3): rep 2, supports 2|1 (its neighbour guard has rep 1). No candidate yet: no 2|0.
  b.step(valid_at(Vec3(3.5, 1, 0)));
  EXPECT_EQ(b.representative(3), 2u);
  EXPECT_EQ(b.interface_supports(2, 1), std::vector<VertexId>{3});
  EXPECT_TRUE(b.shortcuts().empty());
  // y (dense 4): rep 2, supports 2|0; its dense route to x is the edge y-x, 2.0 long, and
  // (2.915 + 2.915) / 2 > 1.05 * 2.0: 0 and 1 (in view of each other) are joined.
  b.step(valid_at(Vec3(1.5, 1, 0)));
  EXPECT_EQ(b.representative(4), 2u);
  EXPECT_EQ(b.roadmap().vertex_count(), 3u) << "a shortcut by edge admits no vertex";
  ASSERT_EQ(b.shortcuts().size(), 1u);
  const ShortcutRecord& r = b.shortcuts().front();
  EXPECT_EQ(r.v, 2u);
  EXPECT_EQ(r.vp, 0u);
  EXPECT_EQ(r.vpp, 1u);
  EXPECT_DOUBLE_EQ(r.sparse_length, kBridgeLength);
  EXPECT_DOUBLE_EQ(r.dense_length, 2.0);
  EXPECT_TRUE(r.direct_edge);
  EXPECT_TRUE(r.path.empty());
  EXPECT_TRUE(b.roadmap().has_edge(0, 1));
  EXPECT_EQ(b.admissions().shortcut_edge, 1u);
  EXPECT_EQ(b.admissions().shortcut_edges, 1u);
  EXPECT_EQ(b.admissions().shortcut_path, 0u);
  // Once 0 and 1 are adjacent the pair is no candidate: the same situation again adds nothing.
  b.step(valid_at(Vec3(1.5, 1.1, 0)));
  EXPECT_EQ(b.shortcuts().size(), 1u);
  EXPECT_EQ(b.roadmap().edge_count(), 3u);
}

TEST(SparsShortcut, DenseRouteOverSparseEstimateOverTAddsNothing) {
  const Scene scene = test::open_scene(2.6, 3.0);
  SparsBuilder b(scene, BuildOptions{}, shortcut_rules());
  place_bridge(b);
  // x and y are 2.68 apart (no dense edge); their route through the bridge is 2 * 1.430 = 2.86:
  // shorter than the sparse estimate 2.915 but not by the factor t (2.915 / 1.05 = 2.78), so the
  // stretch holds.
  b.step(valid_at(Vec3(3.84, 2, 0)));
  b.step(valid_at(Vec3(1.16, 2, 0)));
  EXPECT_EQ(b.representative(3), 2u);
  EXPECT_EQ(b.representative(4), 2u);
  EXPECT_EQ(b.interface_supports(2, 1), std::vector<VertexId>{3});
  EXPECT_EQ(b.interface_supports(2, 0), std::vector<VertexId>{4});
  ASSERT_FALSE(b.dense()->has_edge(3, 4));
  EXPECT_TRUE(b.shortcuts().empty());
  EXPECT_FALSE(b.roadmap().has_edge(0, 1));
  EXPECT_EQ(b.admissions().shortcut_edge + b.admissions().shortcut_path, 0u);
}

TEST(SparsShortcut, NothingWithoutTheRule) {
  const Scene scene = test::open_scene(2.6, 3.0);
  SparsRules rules = shortcut_rules();
  rules.dense_shortcut = false;
  SparsBuilder b(scene, BuildOptions{}, rules);
  place_bridge(b);
  b.step(valid_at(Vec3(3.5, 1, 0)));
  b.step(valid_at(Vec3(1.5, 1, 0)));
  EXPECT_TRUE(b.shortcuts().empty());
  EXPECT_FALSE(b.roadmap().has_edge(0, 1));
}

TEST(SparsShortcut, BlockedPairIsJoinedThroughTheSmoothedDenseRoute) {
  // The wall at x = 2.5 (|y|, |z| <= 1) blocks root-guard. q at (2.5, 1.3, 0) has rep 2 and
  // dense neighbours root and guard: it supports both interfaces (dense route 0). The route
  // root, q, guard cannot be smoothed (root-guard blocked): q becomes sparse vertex 3 on it.
  const Scene scene = test::open_scene(2.9, 3.0, true);
  SparsBuilder b(scene, BuildOptions{}, shortcut_rules());
  place_bridge(b);
  ASSERT_FALSE(scene.segment_valid(Vec3(0, 0, 0), Vec3(5, 0, 0)));
  b.step(valid_at(Vec3(2.5, 1.3, 0)));
  ASSERT_EQ(b.shortcuts().size(), 1u);
  const ShortcutRecord& r = b.shortcuts().front();
  EXPECT_EQ(r.v, 2u);
  EXPECT_EQ(r.vp, 0u);
  EXPECT_EQ(r.vpp, 1u);
  EXPECT_DOUBLE_EQ(r.dense_length, 0.0);
  EXPECT_FALSE(r.direct_edge);
  EXPECT_EQ(r.path, (std::vector<VertexId>{0, 3, 1}));
  EXPECT_EQ(r.front_rep, 0u);
  EXPECT_EQ(r.back_rep, 1u);
  ASSERT_EQ(b.roadmap().vertex_count(), 4u);
  EXPECT_EQ(b.dense_ids()[3], 3u) << "the new sparse vertex is q's dense vertex";
  EXPECT_TRUE(b.roadmap().has_edge(0, 3));
  EXPECT_TRUE(b.roadmap().has_edge(3, 1));
  EXPECT_FALSE(b.roadmap().has_edge(0, 1));
  EXPECT_EQ(b.admissions().shortcut_path, 1u);
  EXPECT_EQ(b.admissions().shortcut_path_vertices, 1u);
  EXPECT_EQ(b.admissions().shortcut_edges, 2u);
  EXPECT_EQ(b.admissions().shortcut_edge, 0u);
}

TEST(SparsShortcut, SamePairInViewIsJoinedByEdgeNotThroughQ) {
  // Without the wall the same situation joins 0 and 1 by an edge, not through q.
  const Scene scene = test::open_scene(2.9, 3.0);
  SparsBuilder b(scene, BuildOptions{}, shortcut_rules());
  place_bridge(b);
  b.step(valid_at(Vec3(2.5, 1.3, 0)));
  ASSERT_EQ(b.shortcuts().size(), 1u);
  EXPECT_TRUE(b.shortcuts().front().direct_edge);
  EXPECT_EQ(b.roadmap().vertex_count(), 3u);
  EXPECT_TRUE(b.roadmap().has_edge(0, 1));
}

}  // namespace
}  // namespace ispars::planning
