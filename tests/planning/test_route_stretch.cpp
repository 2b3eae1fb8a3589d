// measure_route_stretch on a roadmap whose every ratio is known by hand.

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/planning/builders/route_stretch.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

TEST(RouteStretch, BinsAndRatiosMatchAHandComputedRoadmap) {
  const Scene scene = test::open_scene(1.0, 1.5);  // free space: every segment below is valid
  const std::vector<PoiId> sees{0};
  // Sparse: a - b - c (a detour over b), e far away and not joined, f seeing nothing.
  Roadmap sparse(3);
  const VertexId a = sparse.add_vertex(Vec3(0, 0, 0), sees);
  const VertexId b = sparse.add_vertex(Vec3(1, 1, 0), sees);
  const VertexId c = sparse.add_vertex(Vec3(2, 0, 0), sees);
  const VertexId e = sparse.add_vertex(Vec3(10, 0, 0), sees);
  const VertexId f = sparse.add_vertex(Vec3(1, -1, 0), {});
  sparse.add_edge(a, b);
  sparse.add_edge(b, c);
  sparse.add_edge(c, f);
  // Dense: the same samples, plus d between a and c; a - d - c is straight; e joined to c.
  Roadmap dense(3);
  for (VertexId v = 0; v < sparse.vertex_count(); ++v)
    dense.add_vertex(sparse.position(v), sparse.visibility_table().ids(v));
  const VertexId d = dense.add_vertex(Vec3(1, 0, 0), {});
  dense.add_edge(a, b);
  dense.add_edge(b, c);
  dense.add_edge(a, d);
  dense.add_edge(d, c);
  dense.add_edge(c, e);
  const std::vector<VertexId> ids{0, 1, 2, 3, 4};

  RouteStretchOptions options;
  options.big_delta = 1.5;
  options.stretch = 1.05;
  options.bins = 3;
  options.segment_bins = 3;
  const RouteStretchReport r = measure_route_stretch(scene, sparse, dense, ids, options);
  ASSERT_EQ(r.bins.size(), 4u) << "[0,1) [1,2) [2,3) and [3,inf) Delta";
  EXPECT_EQ(r.viewpoints, 4u) << "f sees nothing";
  EXPECT_EQ(r.sources, 4u);
  // [0, 1.5): a-b and b-c, both sqrt 2 apart, routes equal to the segment: ratio 1.
  EXPECT_EQ(r.bins[0].vs_dense.pairs, 2u);
  EXPECT_DOUBLE_EQ(r.bins[0].vs_dense.max, 1.0);
  EXPECT_EQ(r.bins[0].vs_segment.pairs, 2u);
  EXPECT_EQ(r.bins[0].vs_dense.share_over_t, 0.0);
  EXPECT_NEAR(r.bins[0].vs_dense.max_excess, -0.05 * std::sqrt(2.0) / 1.5, 1e-12) << "(d_s - t d) / Delta";
  // [1.5, 3): a-c, 2 apart: sparse 2 sqrt 2 against dense 2 and the segment 2.
  ASSERT_EQ(r.bins[1].vs_dense.pairs, 1u);
  EXPECT_NEAR(r.bins[1].vs_dense.median, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.bins[1].vs_segment.median, std::sqrt(2.0), 1e-12);
  EXPECT_EQ(r.bins[1].vs_dense.share_over_t, 1.0);
  EXPECT_NEAR(r.bins[1].vs_dense.max_excess, (2.0 * std::sqrt(2.0) - 1.05 * 2.0) / 1.5, 1e-12);
  EXPECT_NEAR(r.bins[1].vs_dense.p99, std::sqrt(2.0), 1e-12);
  EXPECT_EQ(r.bins[2].vs_dense.pairs, 0u);
  // [4.5, inf): e with a, b and c; joined in G_d, not in G_s: infinite ratios, counted.
  EXPECT_EQ(r.bins[3].vs_dense.pairs, 3u);
  EXPECT_EQ(r.bins[3].vs_dense.disconnected, 3u);
  EXPECT_TRUE(std::isinf(r.bins[3].vs_dense.median));
  EXPECT_TRUE(std::isinf(r.bins[3].vs_dense.max_excess));
  EXPECT_EQ(r.bins[3].vs_segment.pairs, 0u) << "segments are compared below segment_bins Delta only";
  // Within 3 Delta: the three short pairs together.
  EXPECT_EQ(r.within_3_delta.vs_dense.pairs, 3u);
  EXPECT_DOUBLE_EQ(r.within_3_delta.vs_dense.median, 1.0);
  EXPECT_NEAR(r.within_3_delta.vs_dense.max, std::sqrt(2.0), 1e-12);
  EXPECT_EQ(r.beyond_3_delta.vs_dense.pairs, 3u);
  EXPECT_EQ(r.all.vs_dense.pairs, 6u);
  EXPECT_EQ(r.all.vs_dense.disconnected, 3u);

  // Ten bins of one Delta (the default), segments checked up to 10 Delta: e, 8 to 10 apart from
  // the others (bins 5 and 6), is compared with its segment too.
  options.bins = 10;
  options.segment_bins = 10;
  const RouteStretchReport wide = measure_route_stretch(scene, sparse, dense, ids, options);
  ASSERT_EQ(wide.bins.size(), 11u);
  EXPECT_EQ(wide.bins[5].vs_dense.pairs + wide.bins[6].vs_dense.pairs, 3u);
  EXPECT_EQ(wide.bins[5].vs_segment.pairs + wide.bins[6].vs_segment.pairs, 3u);
  EXPECT_EQ(wide.beyond_3_delta.vs_segment.disconnected, 3u);
  EXPECT_TRUE(std::isinf(wide.bins[10].to));
}

TEST(RouteStretch, PairsOutsideTheDenseComponentAreNotComparedAndSourcesCanBeCapped) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const std::vector<PoiId> sees{1};
  Roadmap sparse(3), dense(3);
  for (int i = 0; i < 6; ++i) {
    sparse.add_vertex(Vec3(i, 0, 0), sees);
    dense.add_vertex(Vec3(i, 0, 0), sees);
  }
  for (VertexId v = 0; v + 1 < 3; ++v) {  // dense joins 0-1-2 only; sparse joins everything
    dense.add_edge(v, v + 1);
  }
  for (VertexId v = 0; v + 1 < 6; ++v) sparse.add_edge(v, v + 1);
  const std::vector<VertexId> ids{0, 1, 2, 3, 4, 5};
  RouteStretchOptions options;
  options.big_delta = 1.5;
  const RouteStretchReport all = measure_route_stretch(scene, sparse, dense, ids, options);
  std::size_t pairs = 0;
  for (const StretchBin& b : all.bins) pairs += b.vs_dense.pairs;
  EXPECT_EQ(pairs, 3u) << "only 0-1, 0-2 and 1-2 are joined in G_d";
  options.max_sources = 2;
  const RouteStretchReport capped = measure_route_stretch(scene, sparse, dense, ids, options);
  EXPECT_EQ(capped.sources, 2u);
}

}  // namespace
}  // namespace ispars::planning
