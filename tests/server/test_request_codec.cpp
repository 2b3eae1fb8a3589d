// The daemon's request decoding and reply encoding, without DDS: a tour's and a verify's replies
// field by field (a BUILD's arguments: tests/wire/test_build_args.cpp).

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/server/request_codec.hpp"
#include "support/test_support.hpp"

namespace ispars::server {
namespace {

TEST(RequestCodec, ATourReplyCarriesTheWalkTheShortcutTheBoundAndTheTraces) {
  service::TourOutcome o;
  o.result.tour.walk = {0, 3, 0};
  o.result.tour.cost = 8.5;
  o.result.tour.covered = {1, 2};
  o.result.targets = {1, 2, 4};
  o.result.trace = {{0.5, 9.0}, {1.25, 8.5}};
  o.result.bound_trace = {{0.75, 6.0}};
  o.result.lower_bound = 6.0;
  o.result.bound_complete = true;
  o.result.validation.closed = true;
  o.result.validation.steps_are_edges = true;
  o.result.validation.covers_targets = true;
  o.result.validation.cost_matches = true;
  o.waypoints = {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(0, 0, 0)};
  o.shortcut.stops = {0, 3};
  o.shortcut.path = {Vec3(0, 0, 0), Vec3(1, 2, 3)};
  o.shortcut.cost = 7.25;
  o.flown_path = {Vec3(0, 0, 0), Vec3(1, 1, 3), Vec3(0, 0, 0)};
  o.flown_sees = {{}, {1, 2, 4}, {}};
  o.flown_cost = 6.5;
  o.flown_valid = true;
  o.stages = {{"walk", 8.5, 1.0}, {"shortcut", 7.25, 1.0}, {"refine", 6.5, 1.5}};
  o.graph_vertices = 40;
  o.graph_edges = 300;
  o.version = 12;
  msg::TourResult m = to_message(o);
  EXPECT_EQ(m.walk(), (std::vector<std::uint32_t>{0, 3, 0}));
  ASSERT_EQ(m.waypoints().size(), 3u);
  EXPECT_EQ(m.waypoints()[1].y(), 2.0);
  EXPECT_EQ(m.shortcut_stops(), (std::vector<std::uint32_t>{0, 3}));
  ASSERT_EQ(m.shortcut_path().size(), 2u);
  EXPECT_EQ(m.shortcut_path()[1].z(), 3.0);
  EXPECT_EQ(m.cost(), 8.5);
  EXPECT_EQ(m.shortcut_cost(), 7.25);
  EXPECT_EQ(m.covered(), 2u);
  EXPECT_EQ(m.target_count(), 3u);
  EXPECT_EQ(m.lower_bound(), 6.0);
  EXPECT_TRUE(m.bound_complete());
  EXPECT_EQ(m.trace(), (std::vector<double>{0.5, 9.0, 1.25, 8.5}));
  EXPECT_EQ(m.bound_trace(), (std::vector<double>{0.75, 6.0}));
  EXPECT_EQ(m.version(), 12u);
  ASSERT_EQ(m.flown_path().size(), 3u);
  EXPECT_EQ(m.flown_path()[1].y(), 1.0);
  EXPECT_EQ(m.flown_sees_offsets(), (std::vector<std::uint32_t>{0, 0, 3, 3}));
  EXPECT_EQ(m.flown_sees(), (std::vector<std::uint32_t>{1, 2, 4}));
  EXPECT_EQ(m.flown_cost(), 6.5);
  ASSERT_EQ(m.stages().size(), 3u);
  EXPECT_EQ(m.stages()[2].name(), "refine");
  EXPECT_EQ(m.stages()[2].seconds(), 1.5);
  EXPECT_EQ(m.graph_vertices(), 40u);
  EXPECT_EQ(m.graph_edges(), 300u);
  EXPECT_TRUE(m.valid());
  // Valid only when every check passed: a flown tour that failed its check spoils it, and so do a
  // bad shortcut and a bad walk.
  o.flown_valid = false;
  EXPECT_FALSE(to_message(o).valid());
  o.flown_valid = true;
  o.shortcut_validation.problem = "a step crosses the mesh";
  EXPECT_FALSE(to_message(o).valid());
  o.shortcut_validation.problem.clear();
  o.result.validation.covers_targets = false;
  EXPECT_FALSE(to_message(o).valid());
  // No bound proven reads as 0.
  o.result.lower_bound.reset();
  EXPECT_EQ(to_message(o).lower_bound(), 0.0);
}

TEST(RequestCodec, AVerifyReplyCarriesEachCountAndThePromise) {
  service::VerifyOutcome v;
  v.report.invalid_vertices = 1;
  v.report.invalid_edges = 2;
  v.report.wrong_costs = 3;
  v.report.sparse_not_dense = 4;
  v.report.invariant_violations = 5;
  v.report.invariant_vertices = 6;
  v.invariant_promised = true;
  const msg::VerifyResult m = to_message(v);
  EXPECT_EQ(m.invalid_vertices(), 1u);
  EXPECT_EQ(m.invalid_edges(), 2u);
  EXPECT_EQ(m.wrong_costs(), 3u);
  EXPECT_EQ(m.sparse_not_dense(), 4u);
  EXPECT_EQ(m.invariant_violations(), 5u);
  EXPECT_EQ(m.invariant_vertices(), 6u);
  EXPECT_TRUE(m.invariant_promised());
  EXPECT_EQ(m.violations(), v.violations());
  EXPECT_GT(m.violations(), 0u);
}

TEST(RequestCodec, AVerifySummaryNamesEachCountAndWhatInvariantOneWasCheckedOn) {
  service::VerifyOutcome v;
  v.report.invalid_edges = 2;
  v.report.invariant_violations = 5;
  v.report.invariant_vertices = 6;
  v.invariant_promised = true;
  EXPECT_EQ(verify_summary(v, 40),
            "invalid vertices 0, invalid edges 2, wrong costs 0, sparse not dense 0, Invariant 1 violations 5 (6 of "
            "40 dense vertices have one)");
  v.report.invariant_samples = 1000;
  v.invariant_promised = false;
  const std::string sampled = verify_summary(v, 40);
  EXPECT_NE(sampled.find("6 of 1000 fresh samples, drawn for this check"), std::string::npos) << sampled;
  EXPECT_NE(sampled.find("; Invariant 1 is not promised by this method"), std::string::npos) << sampled;
  v.report.invariant_samples = 0;
  v.report.invariant_drawn = 3000;
  v.invariant_promised = true;
  EXPECT_EQ(verify_summary(v, 0),
            "invalid vertices 0, invalid edges 2, wrong costs 0, sparse not dense 0, Invariant 1 violations 5 (6 of "
            "the 3000 samples the build drew (drawn again) have one)");
  EXPECT_EQ(v.violations(), 7u) << "on the samples drawn, Invariant 1 is promised: counted";
}

TEST(RequestCodec, APathAndSnapshotChunksAreEncodedWhole) {
  planning::RoadmapPath path;
  path.waypoints = {Vec3(0, 0, 1), Vec3(3, 4, 1)};
  path.length = 5.0;
  const msg::PathResult p = to_message(path);
  ASSERT_EQ(p.waypoints().size(), 2u);
  EXPECT_EQ(p.waypoints()[1].x(), 3.0);
  EXPECT_EQ(p.length(), 5.0);

  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  service::SnapshotSlice slice;
  slice.generation = 9;
  slice.version = 4;
  slice.chunk_count = 2;
  slice.encoded = std::make_shared<const std::string>("abcdef");
  slice.begin = 1;
  slice.end = 4;
  slice.poi_count = scene.pois().size() - 2;  // the roadmap's POIs: a scene with tasks may have more
  const msg::SnapshotChunk first = to_message(slice, &scene);
  EXPECT_EQ(std::string(first.bytes().begin(), first.bytes().end()), "bcd");
  EXPECT_EQ(first.generation(), 9u);
  EXPECT_EQ(first.version(), 4u);
  EXPECT_EQ(first.chunk_count(), 2u);
  EXPECT_EQ(first.pois().size(), scene.pois().size() - 2);
  EXPECT_EQ(first.root().z(), scene.config().root.z());
  slice.chunk_index = 1;
  slice.begin = 4;
  slice.end = 6;
  const msg::SnapshotChunk second = to_message(slice, nullptr);
  EXPECT_EQ(std::string(second.bytes().begin(), second.bytes().end()), "ef");
  EXPECT_TRUE(second.pois().empty()) << "only the first chunk carries the POIs";
}

TEST(RequestCodec, AnUnknownOperationIsNamedByItsCode) {
  EXPECT_EQ(operation_name(msg::BUILD), "build");
  EXPECT_EQ(operation_name(static_cast<msg::Operation>(42)), "operation 42");
}

}  // namespace
}  // namespace ispars::server
