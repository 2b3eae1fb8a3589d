// Integration tests: a real isparsd process on an isolated domain (random id, localhost only),
// driven by real clients over DDS.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

#include "ispars/client/client.hpp"
#include "support/local_daemon.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/roadmap_builder.hpp"
#include "ispars/roadmap_log.hpp"
#include "ispars/scene.hpp"
#include "support/test_support.hpp"

namespace ispars::test {
namespace {

using client::BuildArgs;
using DaemonProcess = client::LocalDaemon;
using client::random_domain;
const auto client_options = client::local_client_options;
using client::Client;
using client::ClientError;

constexpr auto kLong = std::chrono::seconds(120);

class ServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = random_domain();
    scene_dir_ = dir_.path() / "scenes";
    client::write_tank_tower_scenes(scene_dir_, {"s0", "s1", "s2", "s3"});
  }
  std::unique_ptr<DaemonProcess> start(const std::string& id, std::vector<std::string> extra = {}) {
    return std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id), scene_dir_, id, std::move(extra));
  }
  TempDir dir_;
  int domain_ = 0;
  std::filesystem::path scene_dir_;
};

// "s0".."s3" (built by appending: GCC 12 warns falsely on "s" + std::to_string(n)).
std::string scene_name(unsigned n) {
  std::string name = "s";
  name += std::to_string(n);
  return name;
}

BuildArgs ispars_build(std::uint64_t samples, std::uint64_t seed = 1, bool replace = false) {
  BuildArgs a;
  a.method = "ispars";
  a.samples = samples;
  a.seed = seed;
  a.replace = replace;
  return a;
}

// The roadmap an uninterrupted in-process build of `samples` gives: the reference for the daemon.
std::uint64_t reference_digest(const std::filesystem::path& scene_file, std::uint64_t samples, std::uint64_t seed) {
  const Scene scene = Scene::load(scene_file);
  BuildOptions options;
  options.seed = seed;
  const auto builder = make_roadmap_builder(BuildMethod::ispars, scene, options);
  builder->extend(samples);
  return roadmap_digest(builder->roadmap());
}

TEST_F(ServiceTest, EightConcurrentClientsGetTheirOwnRepliesAndNoneIsLost) {
  auto daemon = start("d");
  {
    Client setup(client_options(domain_));
    for (const char* s : {"s0", "s1", "s2", "s3"}) setup.load(s);
  }
  std::atomic<int> answered{0}, crossed{0}, lost{0}, expected_errors{0};
  std::vector<std::thread> threads;
  for (int c = 0; c < 8; ++c) {
    threads.emplace_back([&, c] {
      Client client(client_options(domain_));
      std::mt19937 rng(static_cast<unsigned>(c));
      const std::string own = scene_name(static_cast<unsigned>(c % 4));
      if (c < 4) client.build(own, ispars_build(2000 + 100 * static_cast<unsigned>(c)));
      for (int i = 0; i < 12; ++i) {
        const std::string scene = scene_name(rng() % 4);
        try {
          switch ((c + i) % 4) {
            case 0: {  // extends, racing each other and the builds
              try {
                client.extend(own, 500);
              } catch (const ClientError& e) {
                // A build already running, or no roadmap yet: a correct, named refusal.
                const std::string what = e.what();
                if (e.kind() != ClientError::Kind::rejected ||
                    (what.find("already running") == std::string::npos && what.find("no roadmap") == std::string::npos)) {
                  throw;
                }
                ++expected_errors;
              }
              break;
            }
            case 1: {
              const auto s = client.stats(scene);
              if (s.scene() != scene || s.server_id() != "d") ++crossed;
              break;
            }
            case 2: {
              const Vec3 from(0.0, 0.0, 1.0 + 0.01 * c), to(2.0, -3.0, 4.0);
              try {
                const auto r = client.path(scene, from, to);
                if (r.waypoints().empty() || std::abs(r.waypoints().front().z() - from.z()) > 1e-12 ||
                    r.status().scene() != scene) {
                  ++crossed;
                }
              } catch (const ClientError& e) {
                if (e.kind() != ClientError::Kind::rejected) throw;
                ++expected_errors;  // no roadmap yet on that scene, or the point is not joinable
              }
              break;
            }
            case 3: {
              const auto entries = client.list_scenes();
              if (entries.size() != 4) ++crossed;
              break;
            }
          }
          ++answered;
        } catch (const ClientError& e) {
          ADD_FAILURE() << "client " << c << " call " << i << ": " << e.what();
          ++lost;
        }
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(answered.load(), 8 * 12);
  EXPECT_EQ(lost.load(), 0);
  EXPECT_EQ(crossed.load(), 0);
  // Every roadmap the clients grew is intact.
  Client check(client_options(domain_));
  for (const char* s : {"s0", "s1", "s2", "s3"}) {
    const auto status = check.wait_idle(s, {}, kLong);
    EXPECT_NE(status.state(), msg::SCENE_FAILED) << status.last_error();
    EXPECT_EQ(check.verify(s).violations(), 0u) << s;
  }
  EXPECT_TRUE(daemon->alive());
}

TEST_F(ServiceTest, LateJoinerReplicaEqualsTheServersSnapshot) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client::RoadmapReplica early(client, "s0");  // subscribed before the build
  client.build("s0", ispars_build(30000));
  // Join while the build runs.
  Client late_client(client_options(domain_));
  for (int i = 0; i < 200 && client.stats("s0").samples_done() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  client::RoadmapReplica late(late_client, "s0");
  const auto done = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(done.state(), msg::SCENE_IDLE) << done.last_error();
  ASSERT_TRUE(late.wait_for(done.generation(), done.version(), std::chrono::seconds(30))) << late.last_error();
  ASSERT_TRUE(early.wait_for(done.generation(), done.version(), std::chrono::seconds(30))) << early.last_error();
  const client::Snapshot snapshot = client.snapshot("s0");
  EXPECT_EQ(snapshot.version, done.version());
  const std::uint64_t digest = roadmap_digest(snapshot.roadmap);
  EXPECT_EQ(roadmap_digest(late.roadmap()), digest);
  EXPECT_EQ(roadmap_digest(early.roadmap()), digest);
  EXPECT_EQ(digest, reference_digest(scene_dir_ / "s0.yaml", 30000, 1));
  EXPECT_GT(late.batches_applied(), 0u) << "the late joiner should follow batches after its snapshot";

  // A rebuild (new generation) resyncs both replicas from a snapshot.
  client.build("s0", ispars_build(3000, 7, /*replace=*/true));
  const auto rebuilt = client.wait_idle("s0", {}, kLong);
  ASSERT_TRUE(late.wait_for(rebuilt.generation(), rebuilt.version(), std::chrono::seconds(30))) << late.last_error();
  EXPECT_EQ(roadmap_digest(late.roadmap()), reference_digest(scene_dir_ / "s0.yaml", 3000, 7));
  EXPECT_GE(late.snapshots_taken(), 2u);
}

TEST_F(ServiceTest, KillNineDuringABuildThenRestartRecoversAVerifiedRoadmap) {
  auto daemon = start("d", {"--compact-every", "5"});
  {
    Client client(client_options(domain_));
    client.load("s1");
    client.build("s1", ispars_build(5'000'000, 3));
    for (int i = 0; i < 1500 && client.stats("s1").samples_done() < 20000; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_GE(client.stats("s1").samples_done(), 20000u);
  }
  daemon->kill9();
  // A torn record at the tail, as a crash inside write() leaves it.
  const auto journal = dir_.path() / "data-d" / "s1" / "journal.log";
  ASSERT_TRUE(std::filesystem::exists(journal));
  {
    std::ofstream torn(journal, std::ios::app | std::ios::binary);
    const char partial[] = {static_cast<char>(200), 0, 0, 0, 1, 2, 3, 4, 5, 6};
    torn.write(partial, sizeof(partial));
  }
  daemon = start("d");  // reloads every stored roadmap
  Client client(client_options(domain_));
  const auto recovered = client.stats("s1");
  EXPECT_EQ(recovered.state(), msg::SCENE_IDLE);
  EXPECT_GE(recovered.samples_done(), 20000u);
  EXPECT_GT(recovered.version(), 0u);
  EXPECT_NE(daemon->log().find("torn journal tail"), std::string::npos) << daemon->log();
  const auto verified = client.verify("s1");
  EXPECT_EQ(verified.violations(), 0u) << verified.message();
  // The recovered roadmap is exactly the uninterrupted build's at that many samples, and it
  // extends exactly as if the daemon had never stopped.
  const client::Snapshot at_recovery = client.snapshot("s1");
  EXPECT_EQ(roadmap_digest(at_recovery.roadmap), reference_digest(scene_dir_ / "s1.yaml", recovered.samples_done(), 3));
  client.extend("s1", 2000);
  const auto extended = client.wait_idle("s1", {}, kLong);
  ASSERT_EQ(extended.state(), msg::SCENE_IDLE) << extended.last_error();
  EXPECT_EQ(extended.samples_done(), recovered.samples_done() + 2000);
  EXPECT_EQ(roadmap_digest(client.snapshot("s1").roadmap),
            reference_digest(scene_dir_ / "s1.yaml", extended.samples_done(), 3));
}

TEST_F(ServiceTest, SigtermFinishesTheBatchPersistsAndExitsZero) {
  auto daemon = start("d");
  std::uint64_t before = 0;
  {
    Client client(client_options(domain_));
    client.load("s2");
    client.build("s2", ispars_build(5'000'000, 5));
    for (int i = 0; i < 1500 && client.stats("s2").samples_done() < 5000; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    before = client.stats("s2").samples_done();
  }
  EXPECT_EQ(daemon->terminate(), 0) << daemon->log();
  daemon = start("d");
  Client client(client_options(domain_));
  const auto after = client.stats("s2");
  EXPECT_GE(after.samples_done(), before);
  EXPECT_EQ(after.state(), msg::SCENE_IDLE);
  EXPECT_NE(after.last_error().find(""), std::string::npos);
  EXPECT_EQ(roadmap_digest(client.snapshot("s2").roadmap), reference_digest(scene_dir_ / "s2.yaml", after.samples_done(), 5));
}

TEST_F(ServiceTest, TwoDaemonsSplitScenesAndNeverBothAnswer) {
  auto a = start("alpha");
  auto b = start("beta");
  auto options = client_options(domain_);
  options.server = "alpha";
  Client to_alpha(options);
  options.server = "beta";
  Client to_beta(options);
  EXPECT_EQ(to_alpha.load("s0").server_id(), "alpha");
  EXPECT_EQ(to_beta.load("s1").server_id(), "beta");
  // s0 is alpha's: a load addressed to beta is refused, naming the owner.
  msg::Request load;
  load.kind(msg::LOAD_SCENE);
  load.scene("s0");
  const msg::Reply refused = to_beta.call_raw(load, "beta");
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("owned by daemon alpha"), std::string::npos) << refused.error();
  // Requests go to each scene's owner, whichever client sends them.
  Client any(client_options(domain_));
  EXPECT_EQ(any.stats("s0").server_id(), "alpha");
  EXPECT_EQ(any.stats("s1").server_id(), "beta");
  any.build("s0", ispars_build(1000));
  any.build("s1", ispars_build(1000));
  EXPECT_EQ(any.wait_idle("s0", {}, kLong).server_id(), "alpha");
  EXPECT_EQ(any.wait_idle("s1", {}, kLong).server_id(), "beta");
  // Each daemon lists its own view; both are listed.
  const auto entries = any.list_scenes();
  EXPECT_EQ(entries.size(), 8u);
  int loaded_alpha = 0, loaded_beta = 0;
  for (const auto& e : entries) {
    if (e.loaded() && e.server_id() == "alpha") ++loaded_alpha;
    if (e.loaded() && e.server_id() == "beta") ++loaded_beta;
  }
  EXPECT_EQ(loaded_alpha, 1);
  EXPECT_EQ(loaded_beta, 1);
  // After alpha unloads s0, beta may take it.
  to_alpha.unload("s0");
  EXPECT_EQ(to_beta.call(load, "beta").server_id(), "beta");
}

TEST_F(ServiceTest, EveryBadRequestGetsANamedErrorAndTheDaemonLives) {
  auto daemon = start("d", {"--max-samples", "1000000"});
  Client client(client_options(domain_));
  client.load("s0");
  const auto expect_error = [&](msg::Request r, const std::string& needle) {
    const msg::Reply reply = client.call_raw(r, "d");
    EXPECT_FALSE(reply.ok()) << needle;
    EXPECT_NE(reply.error().find(needle), std::string::npos) << "expected '" << needle << "' in: " << reply.error();
  };
  const auto request = [](msg::RequestKind kind, const std::string& scene) {
    msg::Request r;
    r.kind(kind);
    r.scene(scene);
    r.method("ispars");
    r.samples(100);
    return r;
  };
  expect_error(request(msg::LOAD_SCENE, "no_such_scene"), "no scene 'no_such_scene'");
  expect_error(request(msg::LOAD_SCENE, "../scenes/s0"), "request: scene: '../scenes/s0' is not a scene name");
  expect_error(request(msg::LOAD_SCENE, "a/b"), "is not a scene name");
  expect_error(request(msg::LOAD_SCENE, ""), "is not a scene name");
  expect_error(request(msg::LOAD_SCENE, ".hidden"), "is not a scene name");
  expect_error(request(msg::LOAD_SCENE, std::string(10000, 'x')), "request: scene: is 10000 bytes long");
  expect_error(request(msg::STATS, "s3"), "not loaded on daemon d");
  expect_error(request(msg::EXTEND, "s0"), "has no roadmap to extend");
  expect_error(request(msg::PATH, "s0"), "has no roadmap yet");
  {
    auto r = request(msg::BUILD, "s0");
    r.method("prm");
    expect_error(r, "request: method: 'prm' is not one of");
  }
  {
    auto r = request(msg::BUILD, "s0");
    r.samples(0);
    expect_error(r, "request: samples: must be at least 1");
  }
  {
    auto r = request(msg::BUILD, "s0");
    r.samples(1'000'000'000'000ull);
    expect_error(r, "request: samples: 1000000000000 is more than this daemon allows");
  }
  for (const auto& [name, value, needle] :
       std::vector<std::tuple<std::string, double, std::string>>{
           {"stretch", std::numeric_limits<double>::quiet_NaN(), "overrides.stretch: must be finite"},
           {"dense_delta", -1.0, "dense_delta: must be positive"},
           {"sparse_delta", std::numeric_limits<double>::infinity(), "overrides.sparse_delta: must be finite"},
           {"p_accept", 1.5, "overrides.p_accept: must be a probability"},
           {"colour", 1.0, "overrides.colour: unknown parameter"}}) {
    auto r = request(msg::BUILD, "s0");
    msg::Parameter p;
    p.name(name);
    p.value(value);
    r.overrides().push_back(p);
    expect_error(r, needle);
  }
  {
    auto r = request(msg::BUILD, "s0");
    r.overrides().resize(100);
    expect_error(r, "request: overrides: 100 given; at most 16");
  }
  {
    auto r = request(msg::BUILD, "s0");
    r.kind(static_cast<msg::RequestKind>(99));
    expect_error(r, "request: kind: unknown request kind 99");
  }
  // A build, then requests that conflict with it.
  client.build("s0", ispars_build(900'000));
  expect_error(request(msg::BUILD, "s0"), "already running");
  expect_error(request(msg::EXTEND, "s0"), "already running");
  expect_error(request(msg::UNLOAD_SCENE, "s0"), "cancel it first");
  expect_error(request(msg::DROP, "s0"), "running");
  EXPECT_TRUE(client.cancel("s0").ok());
  client.wait_idle("s0", {}, kLong);
  expect_error(request(msg::BUILD, "s0"), "request: replace: scene 's0' already has a roadmap");
  {
    auto r = request(msg::PATH, "s0");
    r.from().x(std::numeric_limits<double>::quiet_NaN());
    expect_error(r, "path: from: must be three finite numbers");
  }
  {
    auto r = request(msg::PATH, "s0");
    r.from().x(1e9);
    expect_error(r, "path: from: ");
  }
  {
    auto r = request(msg::SNAPSHOT, "s0");
    r.chunk_index(1000);
    expect_error(r, "request: chunk_index: 1000 is past the last chunk");
  }
  {
    auto r = request(msg::SNAPSHOT, "s0");
    r.snapshot_version(1u << 30);
    r.snapshot_generation(12345);
    r.chunk_index(1);
    expect_error(r, "no longer available");
  }
  // Still serving, and the roadmap is intact.
  EXPECT_TRUE(daemon->alive());
  const auto status = client.stats("s0");
  EXPECT_EQ(status.state(), msg::SCENE_IDLE);
  EXPECT_GT(status.samples_done(), 0u);
  EXPECT_EQ(client.verify("s0").violations(), 0u);
}

TEST_F(ServiceTest, ToursAreSearchedByTheDaemonWithProgressAndValidated) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", ispars_build(4000));
  const auto built = client.wait_idle("s0", {}, kLong);
  std::vector<double> seen, bounds;
  const msg::Reply r = client.tour("s0", 1.0, 3, {}, [&](double, double cost, double bound) {
    seen.push_back(cost);
    bounds.push_back(bound);
  });
  EXPECT_TRUE(r.tour_valid());
  EXPECT_EQ(r.covered(), r.target_count());
  EXPECT_EQ(r.target_count(), built.pois_covered_root());
  ASSERT_GE(r.walk().size(), 2u);
  EXPECT_EQ(r.walk().front(), 0u);
  EXPECT_EQ(r.walk().back(), 0u);
  EXPECT_EQ(r.waypoints().size(), r.walk().size());
  EXPECT_EQ(r.tour_version(), built.version());
  ASSERT_GE(r.trace().size(), 2u);
  EXPECT_DOUBLE_EQ(r.trace().back(), r.length());
  EXPECT_LE(r.lower_bound(), r.length());
  EXPECT_GT(r.lower_bound(), 0.0);
  ASSERT_GE(r.bound_trace().size(), 2u) << "the LP bound rose at least once";
  EXPECT_LE(r.bound_trace().back(), r.lower_bound());
  EXPECT_FALSE(seen.empty()) << "no progress was published";
  EXPECT_TRUE(std::any_of(bounds.begin(), bounds.end(), [](double b) { return b > 0.0; })) << "no bound was published";
  // The tour's steps are roadmap edges: check against a snapshot, independently of the daemon.
  const client::Snapshot snapshot = client.snapshot("s0");
  double cost = 0;
  for (std::size_t i = 1; i < r.walk().size(); ++i) {
    ASSERT_TRUE(snapshot.roadmap.has_edge(r.walk()[i - 1], r.walk()[i]));
    cost += (snapshot.roadmap.position(r.walk()[i]) - snapshot.roadmap.position(r.walk()[i - 1])).norm();
  }
  EXPECT_NEAR(cost, r.length(), 1e-9 * cost);
  // A subset of targets, and bad tour requests.
  const msg::Reply two = client.tour("s0", 0.3, 1, {r.walk().size() > 2 ? 0u : 0u});
  EXPECT_TRUE(two.tour_valid());
  EXPECT_EQ(two.target_count(), 1u);
  msg::Request bad;
  bad.kind(msg::TOUR);
  bad.scene("s0");
  bad.budget(-1);
  EXPECT_NE(client.call_raw(bad, "d").error().find("request: budget: must be in (0, 3600]"), std::string::npos);
  bad.budget(std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(client.call_raw(bad, "d").ok());
  bad.budget(0.2);
  bad.targets({999999});
  EXPECT_NE(client.call_raw(bad, "d").error().find("unknown POI ids"), std::string::npos);
  client.load("s1");
  bad.scene("s1");
  bad.targets({});
  EXPECT_NE(client.call_raw(bad, "d").error().find("has no roadmap yet"), std::string::npos);
  EXPECT_TRUE(daemon->alive());
}

TEST_F(ServiceTest, ToursAreBoundedAndCancelStopsThemWithTheirBestTour) {
  // One tour worker: two tours may wait or run, a third is refused at once.
  auto daemon = start("d", {"--workers", "1"});
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", ispars_build(4000));
  (void)client.wait_idle("s0", {}, kLong);
  std::vector<msg::Reply> replies(2);
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
  msg::Request third;
  third.kind(msg::TOUR);
  third.scene("s0");
  third.budget(120.0);
  const msg::Reply refused = client.call_raw(third, "d");
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.error().find("request: kind: busy: 2 tours are queued or running"), std::string::npos)
      << refused.error();
  // CANCEL on the scene stops the running tour, which replies with its best tour; the queued
  // one then starts, and a second CANCEL stops it too.
  const auto t0 = std::chrono::steady_clock::now();
  for (int round = 0; round < 40; ++round) {
    const msg::Reply c = client.cancel("s0");
    EXPECT_TRUE(c.ok()) << c.error();
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    if (!replies[0].walk().empty() && !replies[1].walk().empty()) break;
  }
  for (auto& t : tours) t.join();
  EXPECT_EQ(failures, std::vector<std::string>(2)) << daemon->log();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0)
      << "the tours ran on instead of stopping";
  for (const msg::Reply& r : replies) {
    EXPECT_TRUE(r.ok()) << r.error();
    EXPECT_TRUE(r.tour_valid());
    EXPECT_LE(r.lower_bound(), r.length());
  }
  EXPECT_TRUE(daemon->alive());
  // SIGTERM during a tour: the tour stops, replies with its best tour, and the daemon exits
  // without waiting for the tour's budget (30 s).
  msg::Reply last;
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
  EXPECT_TRUE(last.ok()) << last.error();
  EXPECT_TRUE(last.tour_valid());
}

TEST_F(ServiceTest, NoDaemonIsATimeoutNamingTheDomain) {
  auto options = client_options(domain_);
  options.timeout = std::chrono::milliseconds(1500);
  Client client(options);
  try {
    (void)client.stats("s0");
    FAIL() << "expected no daemon";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.kind(), ClientError::Kind::no_daemon);
    EXPECT_NE(std::string(e.what()).find("DDS domain " + std::to_string(domain_)), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ispars::test
