// The client library's types carry every field of the messages they come from (message_convert.cpp).

#include <gtest/gtest.h>

#include <set>

#include "ispars/client/wire_calls.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::client {
namespace {

msg::SceneStatus full_status() {
  msg::SceneStatus s;
  s.scene("tower");
  s.server_id("d1");
  s.status_seq(3);
  s.state(msg::SCENE_BUILDING);
  s.method("ispars");
  s.variant("alg1");
  s.seed(5);
  s.generation(6);
  s.samples_done(7);
  s.samples_target(8);
  s.version(9);
  s.vertices(10);
  s.edges(11);
  s.components(12);
  s.dense_vertices(13);
  s.dense_edges(14);
  s.poi_count(15);
  s.pois_covered(16);
  s.pois_covered_root(17);
  s.dense_delta(1.5);
  s.sparse_delta(2.5);
  s.stretch(3.5);
  s.stretch_slack(0.25);
  s.stretch_slack_after(18);
  s.p_accept(0.75);
  s.last_error("note");
  s.scene_fingerprint("abc");
  s.builder_version(19);
  s.tasks(20);
  return s;
}

TEST(MessageConvert, AStatusKeepsEveryField) {
  const SceneStatus s = from_message(full_status());
  EXPECT_EQ(s.scene, "tower");
  EXPECT_EQ(s.server_id, "d1");
  EXPECT_EQ(s.status_seq, 3u);
  EXPECT_EQ(s.state, SceneState::building);
  EXPECT_EQ(s.method, "ispars");
  EXPECT_EQ(s.variant, "alg1");
  EXPECT_EQ(s.seed, 5u);
  EXPECT_EQ(s.generation, 6u);
  EXPECT_EQ(s.samples_done, 7u);
  EXPECT_EQ(s.samples_target, 8u);
  EXPECT_EQ(s.version, 9u);
  EXPECT_EQ(s.vertices, 10u);
  EXPECT_EQ(s.edges, 11u);
  EXPECT_EQ(s.components, 12u);
  EXPECT_EQ(s.dense_vertices, 13u);
  EXPECT_EQ(s.dense_edges, 14u);
  EXPECT_EQ(s.poi_count, 15u);
  EXPECT_EQ(s.pois_covered, 16u);
  EXPECT_EQ(s.pois_covered_root, 17u);
  EXPECT_EQ(s.dense_delta, 1.5);
  EXPECT_EQ(s.sparse_delta, 2.5);
  EXPECT_EQ(s.stretch, 3.5);
  EXPECT_EQ(s.stretch_slack, 0.25);
  EXPECT_EQ(s.stretch_slack_after, 18u);
  EXPECT_EQ(s.p_accept, 0.75);
  EXPECT_EQ(s.last_error, "note");
  EXPECT_EQ(s.scene_fingerprint, "abc");
  EXPECT_EQ(s.builder_version, 19u);
  EXPECT_EQ(s.tasks, 20u);
}

TEST(MessageConvert, ATaskEntryKeepsEveryField) {
  msg::TaskEntry t;
  t.name("welds");
  t.first_poi(300);
  t.poi_count(40);
  t.pois_covered(39);
  t.pois_covered_root(38);
  const TaskEntry e = from_message(t);
  EXPECT_EQ(e.name, "welds");
  EXPECT_EQ(e.first_poi, 300u);
  EXPECT_EQ(e.poi_count, 40u);
  EXPECT_EQ(e.pois_covered, 39u);
  EXPECT_EQ(e.pois_covered_root, 38u);
}

TEST(MessageConvert, EveryStateHasItsOwnValueAndTheWiresName) {
  const msg::SceneState all[] = {msg::SCENE_EMPTY,    msg::SCENE_IDLE,   msg::SCENE_QUEUED,  msg::SCENE_REPLAYING,
                                 msg::SCENE_BUILDING, msg::SCENE_FAILED, msg::SCENE_UNLOADED};
  std::set<SceneState> seen;
  for (const msg::SceneState m : all) {
    const SceneState s = from_message(m);
    seen.insert(s);
    EXPECT_EQ(to_string(s), wire::to_string(m));
    EXPECT_EQ(busy(s), m == msg::SCENE_QUEUED || m == msg::SCENE_REPLAYING || m == msg::SCENE_BUILDING);
  }
  EXPECT_EQ(seen.size(), std::size(all));
}

TEST(MessageConvert, ADaemonKeepsItsListsAndRoadmaps) {
  msg::DaemonInfo d;
  d.server_id("d2");
  d.protocol(4);
  d.host("h");
  d.pid(42);
  d.version("0.1.0");
  d.available({"a", "b"});
  d.loaded({"a"});
  d.stored({"b"});
  d.joined_ms(123);
  d.builder_version(7);
  msg::StoredRoadmap r;
  r.scene("b");
  r.generation(2);
  r.samples(300);
  r.target(400);
  r.builder_version(7);
  r.fingerprint("f");
  r.yielded_to("d3");
  d.roadmaps({r});
  const DaemonInfo out = from_message(d);
  EXPECT_EQ(out.server_id, "d2");
  EXPECT_EQ(out.protocol, 4);
  EXPECT_EQ(out.host, "h");
  EXPECT_EQ(out.pid, 42);
  EXPECT_EQ(out.version, "0.1.0");
  EXPECT_EQ(out.available, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(out.loaded, std::vector<std::string>{"a"});
  EXPECT_EQ(out.stored, std::vector<std::string>{"b"});
  EXPECT_EQ(out.joined_ms, 123u);
  EXPECT_EQ(out.builder_version, 7u);
  ASSERT_EQ(out.roadmaps.size(), 1u);
  const StoredRoadmap& s = out.roadmaps[0];
  EXPECT_EQ(s.scene, "b");
  EXPECT_EQ(s.generation, 2u);
  EXPECT_EQ(s.samples, 300u);
  EXPECT_EQ(s.target, 400u);
  EXPECT_EQ(s.builder_version, 7u);
  EXPECT_EQ(s.fingerprint, "f");
  EXPECT_EQ(s.yielded_to, "d3");
}

TEST(MessageConvert, RepliesCarryTheirBodies) {
  msg::Reply m;
  m.server_id("d1");
  m.message("done");
  m.status(full_status());
  msg::TourResult t;
  t.walk({0, 4, 0});
  t.waypoints({wire::to_message(Vec3(1, 2, 3))});
  t.cost(9.5);
  t.covered(3);
  t.target_count(4);
  t.lower_bound(8.5);
  t.valid(true);
  t.trace({0.1, 9.5});
  t.bound_trace({0.2, 8.5});
  t.bound_complete(true);
  t.version(77);
  t.shortcut_stops({0, 4});
  t.shortcut_path({wire::to_message(Vec3(4, 5, 6))});
  t.shortcut_cost(9.0);
  m.body().tour(t);
  const TourReply tour = to_tour_reply(m);
  EXPECT_EQ(tour.server_id, "d1");
  EXPECT_EQ(tour.message, "done");
  EXPECT_EQ(tour.status.vertices, 10u);
  EXPECT_EQ(tour.tour.walk, (std::vector<std::uint32_t>{0, 4, 0}));
  ASSERT_EQ(tour.tour.waypoints.size(), 1u);
  EXPECT_EQ(tour.tour.waypoints[0], Vec3(1, 2, 3));
  EXPECT_EQ(tour.tour.cost, 9.5);
  EXPECT_EQ(tour.tour.covered, 3u);
  EXPECT_EQ(tour.tour.target_count, 4u);
  EXPECT_EQ(tour.tour.lower_bound, 8.5);
  EXPECT_TRUE(tour.tour.valid);
  EXPECT_EQ(tour.tour.trace, (std::vector<double>{0.1, 9.5}));
  EXPECT_EQ(tour.tour.bound_trace, (std::vector<double>{0.2, 8.5}));
  EXPECT_TRUE(tour.tour.bound_complete);
  EXPECT_EQ(tour.tour.version, 77u);
  EXPECT_EQ(tour.tour.shortcut_stops, (std::vector<std::uint32_t>{0, 4}));
  ASSERT_EQ(tour.tour.shortcut_path.size(), 1u);
  EXPECT_EQ(tour.tour.shortcut_path[0], Vec3(4, 5, 6));
  EXPECT_EQ(tour.tour.shortcut_cost, 9.0);

  msg::PathResult p;
  p.waypoints({wire::to_message(Vec3(1, 0, 0)), wire::to_message(Vec3(2, 0, 0))});
  p.length(1.0);
  m.body().path(p);
  const PathReply path = to_path_reply(m);
  EXPECT_EQ(path.path.waypoints, (std::vector<Vec3>{Vec3(1, 0, 0), Vec3(2, 0, 0)}));
  EXPECT_EQ(path.path.length, 1.0);

  msg::VerifyResult v;
  v.violations(1);
  v.invalid_vertices(2);
  v.invalid_edges(3);
  v.wrong_costs(4);
  v.sparse_not_dense(5);
  v.invariant_violations(6);
  v.invariant_vertices(7);
  v.invariant_promised(true);
  m.body().verify(v);
  const Verification got = to_verify_reply(m).verify;
  EXPECT_EQ(got.violations, 1u);
  EXPECT_EQ(got.invalid_vertices, 2u);
  EXPECT_EQ(got.invalid_edges, 3u);
  EXPECT_EQ(got.wrong_costs, 4u);
  EXPECT_EQ(got.sparse_not_dense, 5u);
  EXPECT_EQ(got.invariant_violations, 6u);
  EXPECT_EQ(got.invariant_vertices, 7u);
  EXPECT_TRUE(got.invariant_promised);
}

TEST(MessageConvert, ASceneEntryKeepsItsNote) {
  msg::SceneEntry e;
  e.scene("s0");
  e.loaded(true);
  e.has_roadmap(true);
  e.server_id("d1");
  e.note("yielded");
  const SceneEntry out = from_message(e);
  EXPECT_EQ(out.scene, "s0");
  EXPECT_TRUE(out.loaded);
  EXPECT_TRUE(out.has_roadmap);
  EXPECT_EQ(out.server_id, "d1");
  EXPECT_EQ(out.note, "yielded");
}

}  // namespace
}  // namespace ispars::client
