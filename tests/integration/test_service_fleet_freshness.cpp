// The fleet's freshness rule with real daemons (docs/fleet.md): restarts in any order never
// replace a fresher roadmap, a holder of a stale copy hands the scene to the daemon with the
// fresher one, and the faults a fleet meets (another scene file, another builder version, equal
// copies) each end in a named outcome, in the log and in `ispars scenes list`, with nothing lost.

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <map>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/roadmap/sealed_file.hpp"
#include "ispars/wire/scene_owner.hpp"

#include "integration/metrics_probe.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

// Waits until exactly `id` holds `scene` and serves it idle; returns how long it took (-1: it
// did not within `limit`), and in `announced` how long until the announcements said so.
double wait_held_idle_by(Client& client, const std::string& scene, const std::string& id, std::chrono::seconds limit,
                         double* announced = nullptr) {
  const auto start = Clock::now();
  const auto since = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  double took = -1.0;
  (void)eventually(
      [&] {
        if (holders(client, scene) != std::vector<std::string>{id}) return false;
        if (announced != nullptr && *announced < 0.0) *announced = since();
        try {
          const SceneStatus s = client.stats(scene);
          if (s.server_id == id && s.state == SceneState::idle) took = since();
        } catch (const ClientError&) {  // asked while the scene moves
        }
        return took >= 0.0;
      },
      limit, id + " holds " + scene + " idle", std::chrono::milliseconds(100));
  return took;
}

// Daemons here restart beside running peers. (Over Fast DDS 2.9.1's shared memory transport, once
// part of the localhost profile, a daemon restarted that way on a loaded machine went deaf to its
// peers in 3 tries of 3: the profile has no shared memory transport since.)
class FleetFreshnessTest : public ServiceTest {
 protected:
  std::unique_ptr<DaemonProcess> start(const std::string& id, const std::filesystem::path& scenes = {},
                                       const std::vector<std::string>& extra = {}) {
    return std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id),
                                           scenes.empty() ? scene_dir_ : scenes, id, extra);
  }
  // Daemon `id` alone builds `scene` to `samples` samples, then stops (SIGTERM).
  void build_alone_and_stop(const std::string& id, const std::string& scene, std::uint64_t samples,
                            std::uint64_t seed) {
    auto d = start(id);
    Client client(options());
    client.load(scene);
    client.build(scene, ispars_build(samples, seed));
    ASSERT_EQ(client.wait_idle(scene, {}, kLong).samples_done, samples);
    EXPECT_EQ(d->terminate(), 0);
  }
  client::ClientOptions options() const { return client_options(domain_); }
  // Daemon a notes `outcome` about s2 in its scenes list (within 15 s); then for 3 s b keeps
  // holding s2 and a offers no copy of it.
  static void expect_noted_and_not_offered(Client& client, DaemonProcess& a, DaemonProcess& b,
                                           const std::string& outcome) {
    ASSERT_TRUE(eventually([&] { return note_of(client, "s2", "a").find(outcome) != std::string::npos; }, 15s,
                           "a notes: " + outcome))
        << a.log();
    const auto b_holds_a_offers_none = [&] {
      const auto messages = client::daemon_messages(client);
      return holders(client, "s2") == std::vector<std::string>{"b"} &&
             std::none_of(messages.begin(), messages.end(), [](const msg::DaemonInfo& info) {
               return info.server_id() == "a" && wire::roadmap_of(info, "s2") != nullptr;
             });
    };
    EXPECT_TRUE(throughout(b_holds_a_offers_none, 3s, "b holds s2 and a offers no copy of it", 200ms))
        << a.log() << b.log();
  }
};

// The a/b sequence. O builds 2,000 samples and is killed; P takes over, rebuilds to 2,000
// and is extended to 4,000 (acknowledged). P stops; O restarts alone with its 2,000, then P
// returns: O hands the scene to P, whose 4,000 samples survive O's kill -9, byte for byte an
// uninterrupted build of 4,000.
TEST_F(FleetFreshnessTest, ARestartedStaleOwnerNeverReplacesTheFresherRoadmap) {
  auto one = start("one");
  auto two = start("two");
  Client client(options());
  client.load("s0");
  client.build("s0", ispars_build(2000, 5));
  const std::string o = client.wait_idle("s0", {}, kLong).server_id;
  const std::string p = o == "one" ? "two" : "one";
  auto& owner = o == "one" ? one : two;
  auto& other = o == "one" ? two : one;
  owner->kill9();
  ASSERT_GE(wait_held_idle_by(client, "s0", p, std::chrono::seconds(60)), 0.0) << other->log();
  ASSERT_EQ(client.stats("s0").samples_done, 2000u);
  client.extend("s0", 2000);
  const SceneStatus acked = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(acked.server_id, p);
  ASSERT_EQ(acked.samples_done, 4000u);  // the client's acknowledgement

  EXPECT_EQ(other->terminate(), 0);
  owner = start(o, {}, {"--metrics", "127.0.0.1:0"});  // alone: it loads its own 2,000
  const int o_metrics = metrics_port(owner->log());
  ASSERT_GE(wait_held_idle_by(client, "s0", o, std::chrono::seconds(30)), 0.0) << owner->log();
  const SceneStatus stale = client.stats("s0");
  EXPECT_EQ(stale.samples_done, 2000u);
  // A replica following the stale copy must follow the scene to the fresher one, although its
  // new owner is idle and writes no batch.
  client::RoadmapReplica replica(client, "s0");
  ASSERT_TRUE(replica.wait_for(stale.generation, stale.version, std::chrono::seconds(30))) << replica.last_error();
  other = start(p, {}, {"--metrics", "127.0.0.1:0"});  // with its 4,000: O must hand the scene over
  const int p_metrics = metrics_port(other->log());
  ASSERT_GT(p_metrics, 0) << other->log();
  double held = -1.0;
  const double handover = wait_held_idle_by(client, "s0", p, std::chrono::seconds(30), &held);
  ASSERT_GE(handover, 0.0) << owner->log() << other->log();
  std::printf("handover: %s announced s0 held %.2f s, and answered it idle %.2f s, after it announced itself\n",
              p.c_str(), held, handover);
  EXPECT_EQ(client.stats("s0").samples_done, 4000u);
  EXPECT_NE(owner->log().find("scene 's0' is handed over to daemon " + p + ": its copy is fresher"), std::string::npos)
      << owner->log();
  EXPECT_NE(note_of(client, "s0", o).find("handed over to daemon " + p), std::string::npos);
  // In the metrics too, not only in a log line and the scenes list.
  EXPECT_EQ(metric_on(o_metrics, "ispars_fleet_handed_over{scene=\"s0\",to=\"" + p + "\"}"), 1) << owner->log();
  const SceneStatus fresher = client.stats("s0");
  ASSERT_TRUE(replica.wait_for(fresher.generation, fresher.version, std::chrono::seconds(30)))
      << "the replica stayed on the stale copy: " << replica.version() << " of " << fresher.version;
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client.snapshot("s0").roadmap));

  EXPECT_EQ(other_daemons_counted_on(p_metrics), 1) << "P does not count O before O is killed";
  owner->kill9();
  // Past the lease, P's fleet view, on which it decides takeovers, has lost O: the checks below
  // then show P's answer to O's leave (it reacts within its fleet thread's 100 ms pass).
  ASSERT_TRUE(eventually([&] { return other_daemons_counted_on(p_metrics) == 0; }, 30s, "P notices O's kill -9"))
      << other->log();
  const std::size_t run_start = other->log().rfind("isparsd " + p + " serving");
  EXPECT_TRUE(throughout([&] { return other->log().find("rebuilding", run_start) == std::string::npos; }, 2s,
                         "P rebuilds nothing"))
      << other->log();
  const SceneStatus final_status = client.wait_idle("s0", {}, kLong);
  EXPECT_EQ(final_status.server_id, p);
  EXPECT_EQ(final_status.samples_done, 4000u);
  EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 4000, 5));
  const std::string log = other->log();  // this run's part: after its last start
  EXPECT_EQ(log.find("rebuilding", log.rfind("isparsd " + p + " serving")), std::string::npos) << log;
}

// Two daemons with the same copy: the one the rule names serves it, the other's claim is refused
// naming the equal copies; stopping the server hands it to the other, which rebuilds nothing.
TEST_F(FleetFreshnessTest, TwoEqualCopiesSettleByWeightAndTheOtherContinuesWithoutRebuilding) {
  build_alone_and_stop("first", "s1", 1500, 2);
  std::filesystem::copy(dir_.path() / "data-first", dir_.path() / "data-second",
                        std::filesystem::copy_options::recursive);
  std::filesystem::remove(dir_.path() / "data-second" / ".isparsd.lock");
  auto first = start("first");
  auto second = start("second");
  Client client(options());
  EXPECT_TRUE(eventually([&] { return holders(client, "s1").size() == 1; }, 20s, "one daemon holds s1"));
  const auto held = holders(client, "s1");
  ASSERT_EQ(held.size(), 1u);
  auto& server = held[0] == "first" ? first : second;
  auto& spare = held[0] == "first" ? second : first;
  const std::string spare_id = spare->server_id();
  // The first to start held it alone; the second's claim at its start was refused by name.
  const std::string refused = spare->log() + server->log();
  EXPECT_TRUE(refused.find("is owned by daemon") != std::string::npos ||
              refused.find("equally fresh copies") != std::string::npos)
      << refused;
  EXPECT_EQ(server->terminate(), 0);  // SIGTERM: the spare takes it over at once, from its own copy
  const double took = wait_held_idle_by(client, "s1", spare_id, std::chrono::seconds(30));
  ASSERT_GE(took, 0.0) << spare->log();
  std::printf("SIGTERM takeover: %s served s1 from its own copy %.2f s after the owner stopped\n", spare_id.c_str(),
              took);
  EXPECT_EQ(client.stats("s1").samples_done, 1500u);
  EXPECT_NE(spare->log().find("this daemon's copy (generation"), std::string::npos) << spare->log();
  EXPECT_EQ(spare->log().find("rebuilding"), std::string::npos) << spare->log();
  EXPECT_EQ(roadmap_digest(client.snapshot("s1").roadmap), reference_digest(scene_dir_ / "s1.yaml", 1500, 2));
}

// A DROP is fleet-wide, also once the dropping daemon unloaded the scene and restarted: its drop
// mark weighs like a copy of the drop's generation, so the other daemon's older copy never
// serves the scene again; and when the dropping daemon stops holding it, the other sets its
// older copy aside (kept, named) rather than serve it.
TEST_F(FleetFreshnessTest, ADropOutlivesAnUnloadAndARestartAndSetsTheOlderCopyAside) {
  build_alone_and_stop("first", "s1", 1500, 2);
  std::filesystem::copy(dir_.path() / "data-first", dir_.path() / "data-second",
                        std::filesystem::copy_options::recursive);
  std::filesystem::remove(dir_.path() / "data-second" / ".isparsd.lock");
  std::map<std::string, std::unique_ptr<DaemonProcess>> daemons;
  daemons["first"] = start("first");
  daemons["second"] = start("second");
  Client client(options());
  ASSERT_TRUE(eventually([&] { return holders(client, "s1").size() == 1; }, 20s, "one daemon holds s1"));
  const std::string h = holders(client, "s1")[0];
  const std::string x = h == "first" ? "second" : "first";
  const std::uint64_t built = client.stats("s1").generation;
  client.drop("s1");
  const std::uint64_t dropped = client.stats("s1").generation;
  ASSERT_GT(dropped, built);
  client.unload("s1");
  EXPECT_EQ(daemons[h]->terminate(), 0);
  daemons[h] = start(h);
  // Announced again with the drop's generation, though not loaded.
  const auto drop_announced = [&] {
    for (const auto& info : client::daemon_messages(client)) {
      const msg::StoredRoadmap* r = wire::roadmap_of(info, "s1");
      if (info.server_id() == h && r != nullptr && r->generation() == dropped && r->samples() == 0) return true;
    }
    return false;
  };
  ASSERT_TRUE(eventually(drop_announced, 20s, "the drop is announced")) << daemons[h]->log();
  client.load("s1");
  SceneStatus s = client.stats("s1");
  EXPECT_EQ(s.server_id, h);
  EXPECT_EQ(s.state, SceneState::empty);
  EXPECT_EQ(s.generation, dropped);
  EXPECT_EQ(s.samples_done, 0u) << "the dropped roadmap was served again";
  // The dropping daemon stops while holding the empty scene: the other takes it over from it,
  // and sets its own older copy aside instead of serving it.
  EXPECT_EQ(daemons[h]->terminate(), 0);
  const std::string outcome = "which dropped its roadmap (generation " + std::to_string(dropped) + ")";
  ASSERT_TRUE(eventually([&] { return daemons[x]->log().find(outcome) != std::string::npos; }, 30s,
                         "the other daemon logs: " + outcome))
      << daemons[x]->log();
  s = client.stats("s1");
  EXPECT_EQ(s.server_id, x);
  EXPECT_EQ(s.state, SceneState::empty);
  EXPECT_GT(s.generation, built);
  EXPECT_EQ(client.snapshot("s1").roadmap.vertex_count(), 0u);
  bool kept_aside = false;
  for (const auto& entry : std::filesystem::directory_iterator(dir_.path() / ("data-" + x) / ".aside")) {
    kept_aside |= entry.path().filename().string().rfind("s1-g" + std::to_string(built) + "-1500", 0) == 0;
  }
  EXPECT_TRUE(kept_aside) << "the older copy was not kept aside";
}

// A daemon whose scene file differs from the owner's does not continue the owner's roadmap: it
// says so by name (log, scenes list) and serves its own scene; the owner's store is untouched.
TEST_F(FleetFreshnessTest, ADaemonWithAnotherSceneFileRefusesToContinueTheOwnersRoadmap) {
  const auto other_scenes = dir_.path() / "other-scenes";
  local::write_tank_tower_scenes(other_scenes, {"x0", "s0"});  // its s0 is another tower
  auto owner = start("owner");
  Client client(options());
  client.load("s0");
  client.build("s0", ispars_build(1000, 1));
  ASSERT_EQ(client.wait_idle("s0", {}, kLong).server_id, "owner");
  auto different = start("different", other_scenes);
  // Only a daemon that saw the owner hold the scene knows to take it over: wait until `different`
  // refuses the scene naming its owner.
  std::string refusal;
  ASSERT_TRUE(eventually(
      [&] {
        refusal = call_raw(client, make_change(msg::LOAD_SCENE, "s0"), "different").error();
        return refusal.find("owned by daemon owner") != std::string::npos;
      },
      20s, "`different` refuses s0 naming its owner", 100ms))
      << refusal;
  owner->kill9();
  const std::string outcome = "this daemon's scene file differs from daemon owner's";
  EXPECT_TRUE(eventually([&] { return different->log().find(outcome) != std::string::npos; }, 30s,
                         "`different` logs: " + outcome))
      << different->log();
  EXPECT_NE(note_of(client, "s0", "different").find(outcome), std::string::npos);
  const SceneStatus s = client.stats("s0");
  EXPECT_EQ(s.server_id, "different");
  EXPECT_EQ(s.samples_done, 0u);  // nothing rebuilt from a recipe meant for another scene
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "data-owner" / "s0" / "recipe.json"));
}

// A stored roadmap of another builder version is not offered to the fleet: named in the log and
// the scenes list, and its files are left as they are.
TEST_F(FleetFreshnessTest, AStoreOfAnotherBuilderVersionIsNotOfferedAndLeftUntouched) {
  build_alone_and_stop("d", "s2", 800, 1);
  const auto recipe_path = dir_.path() / "data-d" / "s2" / "recipe.json";
  std::string text;
  {
    std::ifstream in(recipe_path);
    text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  nlohmann::json recipe = nlohmann::json::parse(text);  // as a later builder writes it: sealed
  ASSERT_EQ(recipe.at("builder_version"), 1) << text;
  recipe["builder_version"] = 99;
  text = seal_json(recipe).dump(2) + "\n";
  std::ofstream(recipe_path) << text;
  auto d = start("d");
  Client client(options());
  const std::string outcome = "made by builder version 99, and this daemon has version 1: not offered to the fleet";
  EXPECT_TRUE(eventually([&] { return d->log().find(outcome) != std::string::npos; }, 10s, "d logs: " + outcome))
      << d->log();
  EXPECT_NE(note_of(client, "s2", "d").find(outcome), std::string::npos);
  for (const auto& info : client::daemon_messages(client)) EXPECT_EQ(wire::roadmap_of(info, "s2"), nullptr);
  std::ifstream in(recipe_path);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(after, text);
}

// A copy that cannot be served is not announced: a's copy of s2 is fresher (3,000 samples against
// b's 800) but one bit of its journal's magic is flipped. Before, b handed s2 to a, whose store
// then failed to open, and nobody served s2; now a notes the damage, b keeps serving, and a's
// files are left as they are.
TEST_F(FleetFreshnessTest, ADamagedFresherCopyIsNotOfferedAndTheHealthyHolderKeepsTheScene) {
  build_alone_and_stop("a", "s2", 3000, 1);
  auto b = start("b");
  Client client(options());
  const SceneStatus held = load_and_build(client, "s2", ispars_build(800, 1));
  ASSERT_EQ(held.server_id, "b");
  const auto journal_path = dir_.path() / "data-a" / "s2" / "journal.log";
  std::string journal;
  {
    std::ifstream in(journal_path, std::ios::binary);
    journal.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  journal[3] ^= 0x02;
  std::ofstream(journal_path, std::ios::binary | std::ios::trunc) << journal;
  auto a = start("a");
  expect_noted_and_not_offered(client, *a, *b,
                               "its stored roadmap is damaged: " + journal_path.string() + " does not start as");
  const SceneStatus still = client.stats("s2");
  EXPECT_EQ(still.server_id, "b");
  EXPECT_EQ(still.samples_done, 800u);
  std::ifstream in(journal_path, std::ios::binary);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>()), journal);
}

// The edited scene file. Daemon a holds the fresher copy of s2's lineage (3,000 samples
// against b's 800), but a's scene file was edited since: a cannot serve that copy, so it does not
// offer it, names why in its scenes-list note, and b keeps serving its 800 (before, b handed s2 to
// a, which then served "failed, no roadmap"). Restoring a's file offers the copy again.
TEST_F(FleetFreshnessTest, ACopyBuiltOnAnotherVersionOfTheSceneFileIsNotOffered) {
  const auto a_scenes = dir_.path() / "a-scenes";
  local::write_tank_tower_scenes(a_scenes, {"s0", "s1", "s2", "s3"});
  build_alone_and_stop("a", "s2", 800, 1);
  std::filesystem::create_directories(dir_.path() / "data-b");
  std::filesystem::copy(dir_.path() / "data-a" / "s2", dir_.path() / "data-b" / "s2",
                        std::filesystem::copy_options::recursive);  // b's copy: the same lineage at 800
  {
    auto a = start("a", a_scenes);
    Client client(options());
    client.load("s2");
    (void)client.extend("s2", 2200);
    ASSERT_EQ(client.wait_idle("s2", {}, kLong).samples_done, 3000u);
    ASSERT_EQ(a->terminate(), 0);
  }
  auto b = start("b");
  Client client(options());
  client.load("s2");
  ASSERT_EQ(client.wait_idle("s2", {}, kLong).samples_done, 800u);
  const std::string original = [&] {
    std::ifstream in(a_scenes / "s2.yaml");
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  }();
  std::ofstream(a_scenes / "s2.yaml", std::ios::trunc) << "procedural: {kind: tank_tower, seed: 9}\n";
  auto a = start("a", a_scenes);
  const std::string outcome = "its stored roadmap was built on another version of the scene file";
  expect_noted_and_not_offered(client, *a, *b, outcome);
  EXPECT_EQ(client.stats("s2").samples_done, 800u);
  // The file restored: a's copy is offered again, outweighs b's, and a serves its 3,000 samples.
  std::ofstream(a_scenes / "s2.yaml", std::ios::trunc) << original;
  SceneStatus served;
  EXPECT_TRUE(eventually(
      [&] {
        try {
          served = client.stats("s2");
        } catch (const ClientError&) {  // asked while the scene moves
        }
        return served.server_id == "a" && served.samples_done == 3000u;
      },
      30s, "a serves its 3,000 samples again", 200ms));
  EXPECT_EQ(served.server_id, "a") << a->log() << b->log();
  EXPECT_EQ(served.samples_done, 3000u);
  EXPECT_EQ(note_of(client, "s2", "a").find(outcome), std::string::npos) << "the note goes with the cause";
}

}  // namespace
}  // namespace ispars::test
