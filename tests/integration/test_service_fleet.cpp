// A fleet of daemons on one domain: one owner per scene under the fleet's rule, however many
// daemons claim it at the same instant, and a takeover when the owner dies, which clients follow
// without being told and which rebuilds the same roadmap from the recipe.

#include <gtest/gtest.h>

#include <algorithm>
#include <barrier>
#include <chrono>
#include <thread>

#include "integration/metrics_probe.hpp"
#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/wire/scene_owner.hpp"
#include "support/raw_peer.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

class FleetTest : public ServiceTest {
 protected:
  // Starts daemons `ids` at the same instant (each with `extra`), returns once all announce.
  std::vector<std::unique_ptr<DaemonProcess>> start_together(const std::vector<std::string>& ids,
                                                             const std::vector<std::string>& extra = {}) {
    std::vector<std::unique_ptr<DaemonProcess>> daemons(ids.size());
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      threads.emplace_back([&, i] {
        std::vector<std::string> args = extra;
        args.insert(args.end(), {"--discovery-wait-ms", "1000"});  // the default: daemons starting together
        daemons[i] = start(ids[i], args);
      });
    }
    for (auto& t : threads) t.join();
    return daemons;
  }
};

TEST_F(FleetTest, ThreeDaemonsLoadingOneSceneAtTheSameMomentLeaveExactlyOneOwner) {
  const std::vector<std::string> ids{"east", "west", "north"};
  auto daemons = start_together(ids);
  std::vector<std::unique_ptr<Client>> clients;
  for (std::size_t i = 0; i < ids.size(); ++i) clients.push_back(std::make_unique<Client>(client_options(domain_)));
  Client observer(client_options(domain_));
  for (int round = 0; round < 20; ++round) {
    const std::string scene = scene_name(static_cast<unsigned>(round % 4));
    // Each client addresses a different daemon, all released at once.
    std::barrier go(static_cast<std::ptrdiff_t>(ids.size()));
    std::vector<msg::Reply> replies(ids.size());
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      threads.emplace_back([&, i] {
        go.arrive_and_wait();
        try {
          replies[i] = call_raw(*clients[i], make_change(msg::LOAD_SCENE, scene), ids[i]);
        } catch (const std::exception& e) {
          replies[i].ok(false);
          replies[i].error(e.what());
        }
      });
    }
    for (auto& t : threads) t.join();
    std::vector<std::string> accepted;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      if (replies[i].ok()) {
        accepted.push_back(ids[i]);
      } else {
        EXPECT_NE(replies[i].error().find("daemon"), std::string::npos) << replies[i].error();
      }
    }
    if (accepted.size() != 1u) {
      for (auto& d : daemons) std::fprintf(stderr, "=== %s\n%s\n", d->server_id().c_str(), d->log().c_str());
      for (auto& r : replies) std::fprintf(stderr, "reply: %s\n", r.error().c_str());
    }
    ASSERT_EQ(accepted.size(), 1u) << "round " << round;
    const std::string owner = observer.owner_of(scene);
    EXPECT_EQ(accepted[0], owner) << "round " << round;
    EXPECT_EQ(holders(observer, scene), std::vector<std::string>{owner}) << "round " << round;
    observer.unload(scene);
  }
  for (auto& d : daemons) EXPECT_TRUE(d->alive());
}

TEST_F(FleetTest, DaemonsStartedTogetherWithTheSameSceneToLoadLeaveOneOwner) {
  for (int round = 0; round < 3; ++round) {
    const std::vector<std::string> ids{"a" + std::to_string(round), "b" + std::to_string(round),
                                       "c" + std::to_string(round)};
    auto daemons = start_together(ids, {"--load", "s2"});
    Client observer(client_options(domain_));
    // Each daemon announces, then claims what it preloads: wait for the three claims to settle.
    // Each of the two others was refused its preload, or (announcements slower than the claim
    // window) gave the scene up afterwards.
    const auto settled = [&](const std::unique_ptr<DaemonProcess>& d) {
      const std::string log = d->log();
      return log.find("preload of scene 's2' failed") != std::string::npos ||
             log.find("scene 's2' given up to its owner") != std::string::npos;
    };
    const auto refused = [&] {
      return std::count_if(daemons.begin(), daemons.end(), [&](const auto& d) { return settled(d); });
    };
    EXPECT_TRUE(eventually([&] { return refused() == 2 && holders(observer, "s2").size() == 1; }, 20s,
                           "two daemons refused s2 and one holds it"))
        << "round " << round;
    EXPECT_TRUE(throughout([&] { return holders(observer, "s2").size() == 1; }, 500ms, "one holder of s2"))
        << "round " << round;
    const auto held = holders(observer, "s2");
    ASSERT_EQ(held.size(), 1u) << "round " << round;
    EXPECT_EQ(observer.stats("s2").server_id, held[0]);
    for (auto& d : daemons) {
      if (d->server_id() != held[0]) {
        EXPECT_NE(d->log().find("daemon " + held[0]), std::string::npos);  // the refusal names the owner
      }
    }
    // The positive control of the settled window: the observer's view does follow a change of
    // holders (the holder unloads s2), so the one holder it showed after that window was not a
    // view that had stopped changing.
    observer.unload("s2");
    EXPECT_TRUE(eventually([&] { return holders(observer, "s2").empty(); }, 10s, "the observer sees s2 unloaded"))
        << "round " << round;
    for (auto& d : daemons) EXPECT_EQ(d->terminate(), 0);
  }
}

// What a daemon offers reaches the fleet without a restart: a scene file added to its scene
// directory, and a roadmap it stored, are announced within the 2 s rescan; a removed file leaves.
TEST_F(FleetTest, AnAddedSceneFileAndAStoredRoadmapAreAnnouncedWhileTheDaemonRuns) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  const auto announced = [&](auto field, const std::string& scene) {
    for (const auto& d : client.daemons()) {
      if (d.server_id != "d") continue;
      for (const auto& name : d.*field) {
        if (name == scene) return true;
      }
    }
    return false;
  };
  const auto available = &client::DaemonInfo::available;
  const auto stored = &client::DaemonInfo::stored;
  ASSERT_TRUE(announced(available, "s0"));
  ASSERT_FALSE(announced(available, "s9"));
  local::write_tank_tower_scenes(scene_dir_, {"s9"});
  EXPECT_TRUE(eventually([&] { return announced(available, "s9"); }, 10s,
                         "a scene file added while the daemon runs is announced"));
  std::filesystem::remove(scene_dir_ / "s9.yaml");
  EXPECT_TRUE(eventually([&] { return !announced(available, "s9"); }, 10s, "a removed scene file leaves"));

  client.load("s0");
  EXPECT_FALSE(announced(stored, "s0"));
  client.build("s0", ispars_build(800));
  ASSERT_EQ(client.wait_idle("s0", {}, kLong).state, SceneState::idle);
  EXPECT_TRUE(
      eventually([&] { return announced(stored, "s0"); }, 10s, "a roadmap stored while the daemon runs is announced"));
}

TEST_F(FleetTest, ADaemonWhoseIdIsAlreadyAnnouncedRefusesToStartOrStopsOnceItSeesIt) {
  auto first = start("same");
  // Its own data directory, its own process. It refuses at start when the first's announcement
  // reaches it within its discovery wait; when discovery is slower (a loaded machine), it starts,
  // sees the older namesake and stops by itself.
  try {
    DaemonProcess second(ISPARS_DAEMON, domain_, dir_.path() / "data-second", scene_dir_, "same",
                         {"--discovery-wait-ms", "1000"});
    const std::optional<int> status = second.exit_within(std::chrono::seconds(15));
    ASSERT_TRUE(status.has_value()) << "a second daemon 'same' kept running:\n" << second.log();
    EXPECT_EQ(*status, 3) << second.log();
    EXPECT_NE(second.log().find("server id 'same' is also announced by a daemon that joined DDS domain"),
              std::string::npos)
        << second.log();
  } catch (const std::runtime_error& e) {
    // Refused in its discovery wait, or stopped by the namesake check before it said "serving".
    const std::string what = e.what();
    EXPECT_TRUE(what.find("server id 'same' is already announced on DDS domain") != std::string::npos ||
                what.find("server id 'same' is also announced by a daemon that joined") != std::string::npos)
        << what;
  }
  ASSERT_TRUE(first->alive()) << first->log();
  Client client(client_options(domain_));
  EXPECT_EQ(client.load("s0").server_id, "same");
}

// A running daemon that sees its id announced by another participant: the one that joined the
// domain first keeps serving, whichever way discovery ordered the two.
TEST_F(FleetTest, OfTwoRunningDaemonsWithOneIdTheOneThatJoinedLaterStops) {
  auto daemon = start("same");
  const auto now_ms = static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
  msg::DaemonInfo namesake;
  namesake.server_id("same");
  namesake.protocol(msg::PROTOCOL_VERSION);
  namesake.host("elsewhere");
  namesake.pid(4242);
  {
    RawPeer younger(domain_);  // joined after the daemon: the daemon stays and announces itself again
    namesake.joined_ms(now_ms + 60'000);
    younger.announce(namesake);
    EXPECT_TRUE(eventually([&] { return daemon->log().find("announcing again") != std::string::npos; }, 10s,
                           "the daemon announces itself again"));
    EXPECT_NE(daemon->log().find("announces this daemon's server id 'same'; announcing again"), std::string::npos)
        << daemon->log();
    EXPECT_FALSE(daemon->exit_within(std::chrono::milliseconds(500)).has_value()) << daemon->log();
  }
  {
    RawPeer clockless(domain_);  // a joining time of 0 (no real-time clock, or forged): no time at all
    namesake.joined_ms(0);
    // Announced until the daemon has judged it: a namesake that is not the older one makes the
    // daemon stay and announce itself again (at most once in 5 s), so a second "announcing again"
    // shows this announcement arrived and was judged before the daemon is checked to stay.
    const auto announced_again = [&] {
      const std::string log = daemon->log();
      std::size_t n = 0;
      for (auto at = log.find("announcing again"); at != std::string::npos; at = log.find("announcing again", at + 1)) {
        ++n;
      }
      return n;
    };
    const std::size_t before = announced_again();
    EXPECT_TRUE(eventually(
        [&] {
          clockless.announce(namesake);
          return announced_again() > before;
        },
        15s, "the clockless namesake is judged", 200ms))
        << daemon->log();
    EXPECT_FALSE(daemon->exit_within(std::chrono::milliseconds(1500)).has_value()) << daemon->log();
  }
  RawPeer older(domain_);  // joined a minute before it: the daemon stops
  namesake.joined_ms(now_ms - 60'000);
  older.announce(namesake);
  const std::optional<int> status = daemon->exit_within(std::chrono::seconds(15));
  ASSERT_TRUE(status.has_value()) << daemon->log();
  EXPECT_EQ(*status, 3);
  EXPECT_NE(daemon->log().find("joined DDS domain " + std::to_string(domain_) +
                               " before this one (host elsewhere, pid 4242); this daemon stops"),
            std::string::npos)
      << daemon->log();
}

TEST_F(FleetTest, TwoDaemonsStartedAtTheSameInstantWithOneIdBothRefuse) {
  // Each announces at once and listens: each sees the other's announcement of its own id.
  std::string errors[2];
  std::vector<std::thread> threads;
  for (int i = 0; i < 2; ++i) {
    threads.emplace_back([&, i] {
      try {
        DaemonProcess d(ISPARS_DAEMON, domain_, dir_.path() / ("data-" + std::to_string(i)), scene_dir_, "twin",
                        {"--discovery-wait-ms", "1000"});
        errors[i] = "started:\n" + d.log();
      } catch (const std::runtime_error& e) {
        errors[i] = e.what();  // LocalDaemon: "isparsd exited at start" with its log
      }
    });
  }
  for (auto& t : threads) t.join();
  for (const auto& e : errors) EXPECT_NE(e.find("server id 'twin' is already announced"), std::string::npos) << e;
}

TEST_F(FleetTest, WhenTheOwnerIsKilledAnotherTakesOverAndRebuildsTheSameRoadmap) {
  auto daemons = start_together({"one", "two", "three"});
  Client client(client_options(domain_));
  client.load("s1");
  // A replica following the scene: after the takeover its updates come from another publisher.
  Client watcher(client_options(domain_));
  client::RoadmapReplica replica(watcher, "s1");
  client.build("s1", ispars_build(1500, 3));
  const SceneStatus built = client.wait_idle("s1", {}, kLong);
  const std::uint64_t digest = roadmap_digest(client.snapshot("s1").roadmap);
  ASSERT_TRUE(replica.wait_for(built.generation, built.version, std::chrono::seconds(30)));
  const std::size_t snapshots_before = replica.snapshots_taken();
  const std::string first_owner = built.server_id;
  for (auto& d : daemons) {
    if (d->server_id() == first_owner) d->kill9();
  }
  const auto killed = Clock::now();
  // The client addresses the scene, not a daemon: its next request follows the scene.
  const SceneStatus after = client.stats("s1");
  const double answered_after = std::chrono::duration<double>(Clock::now() - killed).count();
  EXPECT_NE(after.server_id, first_owner);
  std::vector<msg::DaemonInfo> live = client::daemon_messages(client);
  std::erase_if(live, [&](const msg::DaemonInfo& d) { return d.server_id() == first_owner; });
  EXPECT_EQ(after.server_id, wire::assigned_daemon("s1", live));
  // The bound: the participant lease (3 s on localhost), the client's retry (1 s), the claim
  // window (0.3 s) and the scene's load, with room for a loaded 2-core machine.
  EXPECT_LT(answered_after, 12.0) << "the new owner answered " << answered_after << " s after the kill";
  std::printf("takeover: %s answered stats on s1 %.2f s after %s was killed\n", after.server_id.c_str(), answered_after,
              first_owner.c_str());
  const SceneStatus rebuilt = client.wait_idle("s1", {}, kLong);
  EXPECT_EQ(rebuilt.samples_done, built.samples_done);
  EXPECT_EQ(rebuilt.method, "ispars");
  EXPECT_EQ(rebuilt.seed, 3u);
  EXPECT_EQ(roadmap_digest(client.snapshot("s1").roadmap), digest);
  EXPECT_EQ(holders(client, "s1"), std::vector<std::string>{after.server_id});
  // The takeover continues the roadmap's lineage (docs/fleet.md): the same generation, so a
  // replica that already holds that version of it needs no resync (it may take one, as the
  // publisher changed); either way it holds the rebuilt roadmap.
  EXPECT_EQ(rebuilt.generation, built.generation);
  EXPECT_TRUE(replica.wait_for(rebuilt.generation, rebuilt.version, std::chrono::seconds(30)))
      << "replica at generation " << replica.generation() << " version " << replica.version() << "; "
      << replica.last_error();
  EXPECT_GE(replica.snapshots_taken(), snapshots_before);
  EXPECT_EQ(roadmap_digest(replica.roadmap()), digest);
}

// A takeover the new owner cannot make (its memory budget refuses the rebuild) does not leave the
// scene held empty: it is released, the reason is in the scenes list, and the takeover is tried
// again with backoff while nobody holds it; once the former owner returns, it serves its copy.
TEST_F(FleetTest, ATakeoverThatFailsReleasesTheSceneNamesWhyAndIsTriedAgain) {
  auto a = start("a", {"--memory-budget-mb", kNoBudget});
  auto b = start("b", {"--memory-budget-mb", "16"});
  Client client(client_options(domain_));
  ASSERT_TRUE(eventually([&] { return client.daemons().size() == 2; }, 30s, "the client hears both daemons"));
  std::string scene;
  for (unsigned n = 0; n < 4 && scene.empty(); ++n) {
    if (wire::assigned_daemon(scene_name(n), client::daemon_messages(client)) == "a") scene = scene_name(n);
  }
  ASSERT_FALSE(scene.empty()) << "the rule names b for every test scene";
  const SceneStatus built = load_and_build(client, scene, ispars_build(20000, 3));
  ASSERT_EQ(built.server_id, "a");
  const std::uint64_t digest = roadmap_digest(client.snapshot(scene).roadmap);
  a->kill9();
  // b's takeover is refused by its budget: released, named, tried again.
  const auto failures = [&] {
    const std::string log = b->log();
    std::size_t count = 0;
    for (auto at = log.find("taking over scene '" + scene + "' from daemon a failed"); at != std::string::npos;
         at = log.find("taking over scene '" + scene + "' from daemon a failed", at + 1)) {
      ++count;
    }
    return count;
  };
  ASSERT_TRUE(eventually([&] { return failures() >= 2; }, 60s, "b's takeover fails twice", 200ms)) << b->log();
  std::printf("b notes: %s\n", note_of(client, scene, "b").c_str());
  const std::string note = note_of(client, scene, "b");
  EXPECT_NE(note.find("memory budget"), std::string::npos) << note;
  EXPECT_NE(note.find("released, tried again in"), std::string::npos) << note;
  EXPECT_TRUE(holders(client, scene).empty()) << "held empty by " << holders(client, scene)[0];
  // The former owner returns with its copy: it serves it, and b stops trying.
  a = start("a", {"--memory-budget-mb", kNoBudget});
  const SceneStatus served = client.wait_idle(scene, {}, kLong);
  EXPECT_EQ(served.server_id, "a");
  EXPECT_EQ(served.samples_done, built.samples_done);
  EXPECT_EQ(roadmap_digest(client.snapshot(scene).roadmap), digest);
}

// An extend acknowledged while the owner's only worker builds another scene is queued; its target
// is in the owner's status and announcement from the moment it is accepted, so when the owner
// stops (SIGTERM) the daemon that takes the scene over continues to it. Before, the target showed
// only once a worker started the job, and the takeover stopped at the samples done.
TEST_F(FleetTest, AnExtendQueuedWhenTheOwnerStopsIsCarriedOutByTheDaemonThatTakesOver) {
  auto a = start("a", {"--workers", "1", "--memory-budget-mb", kNoBudget});
  Client client(client_options(domain_));
  const SceneStatus x = load_and_build(client, "s0", ispars_build(3000, 3));
  ASSERT_EQ(x.server_id, "a");
  client.load("s1");
  client.build("s1", ispars_build(1'000'000, 3));  // keeps a's only worker busy
  client.extend("s0", 5000);
  const SceneStatus queued = client.stats("s0");
  EXPECT_EQ(queued.state, SceneState::queued);
  EXPECT_EQ(queued.samples_target, 8000u) << "the accepted target is not in the status";
  auto b = start("b", {"--memory-budget-mb", kNoBudget, "--metrics", "127.0.0.1:0"});
  // b has a's announcement (which carries the target) once it counts a.
  const int b_metrics = metrics_port(b->log());
  ASSERT_TRUE(eventually([&] { return other_daemons_counted_on(b_metrics) == 1; }, 30s, "b counts a")) << b->log();
  EXPECT_EQ(a->terminate(), 0);
  // b is named the owner a moment before it has claimed s0: a request in that moment is refused
  // ("not loaded on daemon b"), and the client asks again (bounded).
  std::vector<std::string> refusals;
  const SceneStatus carried = idle_on(client, "s0", "b", 60s, &refusals);
  for (const std::string& refusal : refusals)
    EXPECT_NE(refusal.find("is not loaded on daemon b"), std::string::npos) << refusal;
  EXPECT_EQ(carried.server_id, "b");
  EXPECT_EQ(carried.samples_done, 8000u) << b->log();
  EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 8000, 3));
}

// The vanishing task. The owner's tasks travel on ispars/tasks; when it stops, the daemon
// that takes the scene over rebuilds its roadmap with them (a task's POIs keep their ids), and
// its note names them. The former owner returning with its copy (the same generation, samples and
// task events) changes nothing. Before, the new owner served the roadmap without the task, and
// kept doing so after the former owner returned.
TEST_F(FleetTest, ATaskIsCarriedByTheDaemonThatTakesTheSceneOver) {
  auto a = start("a", {"--memory-budget-mb", kNoBudget});
  Client client(client_options(domain_));
  ASSERT_EQ(load_and_build(client, "s0", ispars_build(1500, 3)).server_id, "a");
  client.add_sampled_task("s0", "weld-seams", 48, 7);
  const SceneStatus with_task = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(with_task.tasks, 1u) << with_task.last_error;
  auto b = start("b", {"--memory-budget-mb", kNoBudget, "--metrics", "127.0.0.1:0"});
  const int b_metrics = metrics_port(b->log());
  ASSERT_TRUE(
      eventually([&] { return metric_on(b_metrics, "ispars_fleet_tasks_known") == 1; }, 30s, "b knows a's task"))
      << b->log();
  EXPECT_EQ(a->terminate(), 0);
  std::vector<std::string> refusals;  // b named the owner a moment before it claims s0
  const SceneStatus carried = idle_on(client, "s0", "b", 60s, &refusals);
  for (const std::string& refusal : refusals)
    EXPECT_NE(refusal.find("is not loaded on daemon b"), std::string::npos) << refusal;
  ASSERT_EQ(carried.server_id, "b") << b->log();
  EXPECT_EQ(carried.samples_done, 1500u);
  EXPECT_EQ(carried.tasks, 1u) << "the task vanished in the takeover: " << b->log();
  EXPECT_EQ(carried.poi_count, with_task.poi_count);
  EXPECT_EQ(carried.generation, with_task.generation);
  const auto tasks = client.tasks("s0");
  ASSERT_EQ(tasks.size(), 1u);
  EXPECT_EQ(tasks[0].name, "weld-seams");
  EXPECT_EQ(tasks[0].poi_count, 48u);
  EXPECT_NE(note_of(client, "s0", "b").find("with its 1 task (weld-seams)"), std::string::npos)
      << note_of(client, "s0", "b");
  // a returns with its copy: equally fresh (generation, samples, task events), so b keeps it.
  a = start("a", {"--memory-budget-mb", kNoBudget});
  EXPECT_TRUE(
      throughout([&] { return holders(client, "s0") == std::vector<std::string>{"b"}; }, 4s, "b alone holds s0", 200ms))
      << a->log() << b->log();
  EXPECT_EQ(client.tasks("s0").size(), 1u);
}

// The held-empty scene, with a third daemon. The rule names b for the scene, but b's
// budget refuses the rebuild: b declines the scene in its announcement until its retry, so the
// rule names c, which takes the scene over and rebuilds it, byte for byte. Before, b kept
// retrying alone and nobody served the scene.
TEST_F(FleetTest, ATakeoverThatFailsPassesToTheNextDaemonTheRuleNames) {
  // The roles by the rule's weights for s0 (no copies yet): the first holds it, the second (a
  // small budget) is named next, the third after it.
  std::vector<std::string> ids{"a", "b", "c"};
  std::sort(ids.begin(), ids.end(),
            [](const std::string& x, const std::string& y) { return wire::outranks("s0", x, y); });
  auto owner = start(ids[0], {"--memory-budget-mb", kNoBudget});
  auto weak = start(ids[1], {"--memory-budget-mb", "16"});
  auto rescuer = start(ids[2], {"--memory-budget-mb", kNoBudget});
  Client client(client_options(domain_));
  ASSERT_TRUE(eventually([&] { return client.daemons().size() == 3; }, 30s, "the client hears the three daemons"));
  const SceneStatus built = load_and_build(client, "s0", ispars_build(20000, 3));
  ASSERT_EQ(built.server_id, ids[0]);
  const std::uint64_t digest = roadmap_digest(client.snapshot("s0").roadmap);
  owner->kill9();
  SceneStatus served;
  EXPECT_TRUE(eventually(
      [&] {
        served = idle_on(client, "s0", ids[2], 1s);  // the scene moves meanwhile
        return served.server_id == ids[2] && served.samples_done == built.samples_done;
      },
      90s, "the third daemon serves every sample"));
  EXPECT_EQ(served.server_id, ids[2]) << weak->log() << rescuer->log();
  EXPECT_EQ(served.samples_done, built.samples_done);
  EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), digest);
  EXPECT_NE(weak->log().find("taking over scene 's0' from daemon " + ids[0] + " failed"), std::string::npos)
      << weak->log();
}

}  // namespace
}  // namespace ispars::test
