// Integration tests of tours through the daemon: progress, validation against a snapshot, bad
// tour requests, admission, CANCEL and SIGTERM during a tour.

#include <atomic>
#include <limits>
#include <set>
#include <thread>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

TEST_F(ServiceTest, ToursAreSearchedByTheDaemonWithProgressAndValidated) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  const auto built = load_and_build(client, "s0", ispars_build(4000));
  std::vector<double> seen, bounds;
  const auto reply = client.tour("s0", 1.0, 3, {}, [&](double, double cost, double bound) {
    seen.push_back(cost);
    bounds.push_back(bound);
  });
  const Tour& r = reply.tour;
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.covered, r.target_count);
  EXPECT_EQ(r.target_count, built.pois_covered_root);
  ASSERT_GE(r.walk.size(), 2u);
  EXPECT_EQ(r.walk.front(), 0u);
  EXPECT_EQ(r.walk.back(), 0u);
  EXPECT_EQ(r.waypoints.size(), r.walk.size());
  EXPECT_EQ(r.version, built.version);
  ASSERT_GE(r.trace.size(), 2u);
  EXPECT_DOUBLE_EQ(r.trace.back(), r.cost);
  EXPECT_LE(r.lower_bound, r.cost);
  EXPECT_GT(r.lower_bound, 0.0);
  ASSERT_GE(r.bound_trace.size(), 2u) << "the LP bound rose at least once";
  EXPECT_LE(r.bound_trace.back(), r.lower_bound);
  EXPECT_FALSE(seen.empty()) << "no progress was published";
  EXPECT_TRUE(std::any_of(bounds.begin(), bounds.end(), [](double b) { return b > 0.0; })) << "no bound was published";
  // The tour's steps are roadmap edges: check against a snapshot, independently of the daemon.
  const client::Snapshot snapshot = client.snapshot("s0");
  double cost = 0;
  for (std::size_t i = 1; i < r.walk.size(); ++i) {
    ASSERT_TRUE(snapshot.roadmap.has_edge(r.walk[i - 1], r.walk[i]));
    cost += (snapshot.roadmap.position(r.walk[i]) - snapshot.roadmap.position(r.walk[i - 1])).norm();
  }
  EXPECT_NEAR(cost, r.cost, 1e-9 * cost);
  // The shortcut tour, checked here with the test's own copy of the scene: its stops are walk
  // vertices, each step an edge or a segment the collision checker accepts, every target still
  // seen from a stop, and its length the sum of its steps, never above the walk's.
  const planning::Scene scene = planning::Scene::load(scene_dir_ / "s0.yaml");
  ASSERT_GE(r.shortcut_stops.size(), 2u);
  ASSERT_EQ(r.shortcut_path.size(), r.shortcut_stops.size());
  EXPECT_EQ(r.shortcut_stops.front(), 0u);
  EXPECT_EQ(r.shortcut_stops.back(), 0u);
  double flown = 0;
  std::vector<std::uint64_t> seen_from_stops(snapshot.roadmap.visible(0).size(), 0);
  for (std::size_t i = 0; i < r.shortcut_stops.size(); ++i) {
    const VertexId v = r.shortcut_stops[i];
    ASSERT_NE(std::find(r.walk.begin(), r.walk.end(), v), r.walk.end()) << "stop " << i;
    unite(seen_from_stops, snapshot.roadmap.visible(v));
    if (i == 0) continue;
    const VertexId u = r.shortcut_stops[i - 1];
    const Vec3 a = snapshot.roadmap.position(u), b = snapshot.roadmap.position(v);
    EXPECT_TRUE(snapshot.roadmap.has_edge(u, v) || scene.segment_valid(a, b)) << "step " << i;
    flown += (b - a).norm();
  }
  EXPECT_NEAR(flown, r.shortcut_cost, 1e-9 * flown);
  EXPECT_LE(r.shortcut_cost, r.cost * (1 + 1e-12));
  EXPECT_EQ(count(seen_from_stops), r.covered);  // every target (here: every POI seen from the root's component)
  // The flown tour, checked the same way: closed at the root, every stop valid, every segment
  // collision-free, every target seen from some stop by rays the test casts, no longer than the
  // shortcut; and the roadmap it came from unchanged (the corridor lives in the tour's graph).
  ASSERT_GE(r.flown_path.size(), 2u);
  EXPECT_EQ(r.flown_path.front(), scene.config().root);
  EXPECT_EQ(r.flown_path.back(), scene.config().root);
  ASSERT_EQ(r.flown_sees.size(), r.flown_path.size());
  std::set<PoiId> seen_flown;
  double flown_length = 0;
  for (std::size_t i = 0; i < r.flown_path.size(); ++i) {
    EXPECT_TRUE(scene.point_valid(r.flown_path[i])) << "stop " << i;
    const std::vector<PoiId> sees = scene.visibility().visible_pois(r.flown_path[i]);
    seen_flown.insert(sees.begin(), sees.end());
    for (const std::uint32_t p : r.flown_sees[i]) EXPECT_TRUE(std::binary_search(sees.begin(), sees.end(), p));
    if (i == 0) continue;
    EXPECT_TRUE(scene.segment_valid(r.flown_path[i - 1], r.flown_path[i])) << "flown step " << i;
    flown_length += (r.flown_path[i] - r.flown_path[i - 1]).norm();
  }
  EXPECT_NEAR(flown_length, r.flown_cost, 1e-9 * flown_length);
  EXPECT_LE(r.flown_cost, r.shortcut_cost * (1 + 1e-12));
  EXPECT_GE(seen_flown.size(), r.covered);
  ASSERT_GE(r.stages.size(), 2u);
  EXPECT_EQ(r.stages.front().name, "walk");
  EXPECT_DOUBLE_EQ(r.stages.back().cost, r.flown_cost);
  EXPECT_GE(r.graph_edges, snapshot.roadmap.edge_count());
  EXPECT_EQ(snapshot.version, built.version) << "the tour changed the roadmap";
  // A subset of targets, and bad tour requests.
  const Tour two = client.tour("s0", 0.3, 1, {0u}).tour;
  EXPECT_TRUE(two.valid);
  EXPECT_EQ(two.target_count, 1u);
  msg::QueryRequest bad = make_query(msg::TOUR, "s0");
  bad.args().tour().budget(-1);
  EXPECT_NE(call_raw(client, bad, "d").error().find("request: budget: must be in (0, 3600]"), std::string::npos);
  bad.args().tour().budget(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(call_raw(client, bad, "d").ok());
  bad.args().tour().budget(0.2);
  bad.args().tour().targets({999999});
  EXPECT_NE(call_raw(client, bad, "d").error().find("unknown POI ids"), std::string::npos);
  client.load("s1");
  bad.scene("s1");
  bad.args().tour().targets({});
  EXPECT_NE(call_raw(client, bad, "d").error().find("has no roadmap yet"), std::string::npos);
  EXPECT_TRUE(daemon->alive());
}

TEST_F(ServiceTest, ToursAreBoundedAndCancelStopsThemWithTheirBestTour) {
  // One tour worker: two tours may wait or run, a third is refused at once.
  auto daemon = start("d", {"--workers", "1"});
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", ispars_build(4000));
  (void)client.wait_idle("s0", {}, kLong);
  std::vector<client::TourReply> replies(2);
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < 2; ++i) {
    clients.push_back(std::make_unique<Client>(client_options(domain_)));
    (void)clients.back()->stats("s0");  // matched with the daemon before the tours start
  }
  std::vector<std::string> failures(2);
  std::vector<std::thread> tours;
  for (int i = 0; i < 2; ++i) {
    tours.emplace_back([&, i] {
      try {
        replies[static_cast<std::size_t>(i)] = clients[static_cast<std::size_t>(i)]->tour("s0", 120.0, 1, {});
      } catch (const std::exception& e) {
        failures[static_cast<std::size_t>(i)] = e.what();
      }
    });
  }
  struct JoinAll {
    std::vector<std::thread>& threads;
    ~JoinAll() {
      for (auto& t : threads) {
        if (t.joinable()) t.join();
      }
    }
  } join_all{tours};
  // Both are admitted well within 2 s on loopback: a third is then refused at once, naming why.
  std::this_thread::sleep_for(std::chrono::seconds(2));
  msg::QueryRequest third = make_query(msg::TOUR, "s0");
  third.args().tour().budget(120.0);
  const msg::Reply refused = call_raw(client, third, "d");
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("request: kind: busy: 2 tours are queued or running"), std::string::npos)
      << refused.error();
  // CANCEL on the scene stops both: the running tour replies with its best tour, the queued one
  // is refused by name (it has no tour to give).
  const auto t0 = std::chrono::steady_clock::now();
  const auto c = client.cancel("s0");
  EXPECT_NE(c.message.find("2 tours stopped"), std::string::npos) << c.message;
  for (auto& t : tours) t.join();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0)
      << "the tours ran on instead of stopping";
  int ran = 0, refused_queued = 0;
  for (std::size_t i = 0; i < 2; ++i) {
    if (failures[i].empty()) {
      const client::TourReply& r = replies[i];
      EXPECT_TRUE(r.tour.valid);
      EXPECT_LE(r.tour.lower_bound, r.tour.cost);
      ++ran;
    } else if (failures[i].find("request: scene: the tour was cancelled before it started") != std::string::npos) {
      ++refused_queued;
    } else {
      ADD_FAILURE() << failures[i];
    }
  }
  EXPECT_EQ(ran, 1);
  EXPECT_EQ(refused_queued, 1);
  EXPECT_TRUE(daemon->alive());
  // Unload and load again while a tour runs: the tour keeps its roadmap and replies, and the
  // load does not wait for it (the unload released the store).
  {
    const std::uint64_t vertices = client.stats("s0").vertices;
    client::TourReply during;
    std::string during_failure;
    std::thread touring([&] {
      try {
        during = clients[1]->tour("s0", 3.0, 4, {});
      } catch (const std::exception& e) {
        during_failure = e.what();
      }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(800));
    EXPECT_NO_THROW(client.unload("s0"));
    const auto reloaded = client.load("s0");
    EXPECT_EQ(reloaded.status.vertices, vertices);
    touring.join();
    EXPECT_EQ(during_failure, "");
    EXPECT_TRUE(during.tour.valid);
  }
  // SIGTERM during a tour: the tour stops, replies with its best tour, and the daemon exits
  // without waiting for the tour's budget (30 s).
  client::TourReply last;
  std::string last_failure;
  std::thread running([&] {
    try {
      last = clients[0]->tour("s0", 30.0, 2, {});
    } catch (const std::exception& e) {
      last_failure = e.what();
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_EQ(daemon->terminate(), 0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count(), 10.0)
      << "SIGTERM waited for the tour";
  running.join();
  EXPECT_EQ(last_failure, "");
  EXPECT_TRUE(last.tour.valid);
}

}  // namespace
}  // namespace ispars::test
