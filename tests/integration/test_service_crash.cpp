// kill -9 at many moments across a roadmap's life (build, extend with compactions, the resume an
// extend starts with after a restart, a replacing build, a drop): every restart recovers a
// committed roadmap that verifies and equals the uninterrupted build at its sample count, holds at
// least what the last status a client saw before the kill acknowledged, and extending it gives
// the uninterrupted build's roadmap byte for byte. (kill -9 keeps the page cache: what a power
// cut does to unsynced writes is the store's power-cut campaign, test_roadmap_store_power_cut.)

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <random>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::test {
namespace {

// The uninterrupted in-process builds, one per seed, extended as the checks need.
class References {
 public:
  explicit References(std::filesystem::path scene_file) : scene_(planning::Scene::load(scene_file)) {}
  std::uint64_t digest(std::uint64_t seed, std::uint64_t samples) {
    auto& builder = builders_[seed];
    if (!builder || builder->samples() > samples) {
      planning::BuildOptions options;
      options.seed = seed;
      builder = planning::make_roadmap_builder(BuildMethod::ispars, scene_, options);
    }
    builder->extend(samples - builder->samples());
    return roadmap_digest(builder->roadmap());
  }

 private:
  planning::Scene scene_;
  std::map<std::uint64_t, std::unique_ptr<planning::RoadmapBuilder>> builders_;
};

class CrashTest : public ServiceTest {
 protected:
  std::unique_ptr<DaemonProcess> start_daemon() {
    return start("d", {"--compact-every", "3", "--discovery-wait-ms", "100", "--memory-budget-mb", kNoBudget});
  }
};

TEST_F(CrashTest, KillNineAtFiftyMomentsLosesNoCommitAndReplaysByteForByte) {
  // 50 in the Release pass; 8 in the sanitizer pass (its reduced scale), where each restart costs
  // several times as much and the 50-kill campaign has already run.
  const std::size_t kills = scaled(50) < 50 ? 8 : 50;
  References references(scene_dir_ / "s0.yaml");
  std::mt19937_64 rng(20261124);
  std::map<std::string, int> killed_in;  // the scene's state seen last before each kill
  std::uint64_t seed = 5;
  std::uint64_t committed_before = 0;  // samples of the roadmap before the interrupted operation
  auto daemon = start_daemon();
  std::string operation;              // the one interrupted last
  std::optional<SceneStatus> seen;    // the last status a client saw before the kill
  std::size_t compared_with_ack = 0;  // restarts compared with an acknowledged status
  for (std::size_t k = 0; k < kills; ++k) {
    try {
      Client client(client_options(domain_));
      (void)client.load("s0");  // loaded at start when stored; loaded now otherwise
      const SceneStatus before = client.stats("s0");
      const bool has_roadmap = !before.method.empty();
      // The operation to interrupt.
      msg::ChangeRequest request = make_change(msg::BUILD, "s0");
      const int pick = has_roadmap ? static_cast<int>(rng() % 4) : 0;
      if (pick == 0 || pick == 1) {  // a build, or a replacing build with the other seed
        operation = has_roadmap ? "replace" : "build";
        seed = has_roadmap ? (before.seed == 5 ? 6 : 5) : 5;
        request.args().build().method("ispars");
        request.args().build().samples(20000);
        request.args().build().seed(seed);
        request.args().build().replace(has_roadmap);
      } else if (pick == 2) {  // an extend: resumed first (after every restart), then compactions
        operation = "extend";
        request = make_change(msg::EXTEND, "s0");
        request.args().extend().samples(12000);
      } else {
        operation = "drop";
        request = make_change(msg::DROP, "s0");
      }
      committed_before = before.samples_done;
      // Sent once (no retry), from a client that gives up quickly: the kill may come before the reply.
      auto fire_options = client_options(domain_);
      fire_options.timeout = std::chrono::milliseconds(500);
      fire_options.retry_interval = std::chrono::seconds(60);
      Client fire(fire_options);
      (void)fire.daemons();
      std::thread sender([&] {
        try {
          (void)call_raw(fire, request, "d");
        } catch (const std::exception&) {
          // killed before it answered
        }
      });
      const auto delay = std::chrono::milliseconds(rng() % 2000);
      std::this_thread::sleep_for(delay);
      seen = client.latest_status("s0");
      ++killed_in[operation + "/" + (seen ? std::string(to_string(seen->state)) : std::string("?"))];
      daemon->kill9();
      sender.join();
      daemon = start_daemon();

      Client after(client_options(domain_));
      (void)after.load("s0");
      // The interrupted job was resumed at start: cancelled here, so what is checked is a
      // committed roadmap (what the kill left, and whatever the resumed job committed since).
      (void)after.cancel("s0");
      const SceneStatus recovered = after.wait_idle("s0", {}, kLong);
      ASSERT_NE(recovered.state, SceneState::failed)
          << "kill " << k << " in " << operation << ": " << recovered.last_error << "\n"
          << daemon->log();
      if (recovered.method.empty()) {
        EXPECT_TRUE(operation == "drop" || !has_roadmap) << "kill " << k << ": the roadmap vanished in " << operation;
        EXPECT_TRUE(!seen || seen->method.empty() || operation == "drop")
            << "kill " << k << ": a roadmap a status acknowledged is gone";
        continue;
      }
      EXPECT_FALSE(operation == "drop" && seen && seen->method.empty() && has_roadmap)
          << "kill " << k << ": an acknowledged drop came back";
      // A committed roadmap: never less than before an extend, the old one or the new one's first
      // commits after a replacing build.
      if (operation == "extend") {
        EXPECT_GE(recovered.samples_done, committed_before) << "kill " << k;
      }
      if (operation == "replace" && recovered.seed != seed) {
        EXPECT_EQ(recovered.samples_done, committed_before) << "kill " << k << ": the old roadmap was cut";
      }
      // A status is published only once the commit it counts is durable: the last one a client saw
      // before the kill is an acknowledgement. The same roadmap (generation) holds at least its
      // samples; another one only replaced it (a replacing build committed after that status).
      if (seen && !seen->method.empty()) {
        if (recovered.generation == seen->generation) {
          EXPECT_GE(recovered.samples_done, seen->samples_done)
              << "kill " << k << " in " << operation << ": an acknowledged commit was lost";
          ++compared_with_ack;
        } else {
          EXPECT_EQ(operation, "replace")
              << "kill " << k << ": generation " << seen->generation << " became " << recovered.generation;
          EXPECT_GT(recovered.generation, seen->generation) << "kill " << k;
        }
      }
      EXPECT_GT(recovered.samples_done, 0u);
      const auto verified = after.verify("s0");
      EXPECT_EQ(verified.verify.violations, 0u) << "kill " << k << ": " << verified.message;
      EXPECT_EQ(roadmap_digest(after.snapshot("s0").roadmap), references.digest(recovered.seed, recovered.samples_done))
          << "kill " << k << " in " << operation << " at " << recovered.samples_done << " samples";
      if (k % 5 == 4) {  // extending to a fixed count: the uninterrupted build's roadmap exactly
        const std::uint64_t target = recovered.samples_done + 1500;
        after.extend("s0", 1500);
        const SceneStatus extended = after.wait_idle("s0", {}, kLong);
        ASSERT_EQ(extended.samples_done, target) << extended.last_error;
        EXPECT_EQ(roadmap_digest(after.snapshot("s0").roadmap), references.digest(extended.seed, target))
            << "kill " << k;
      }
    } catch (const std::exception& e) {
      const std::string log = daemon->log();  // every restart's: the end tells
      FAIL() << "kill " << k << " in " << operation << ": " << e.what() << "\n...\n"
             << log.substr(log.size() > 12000 ? log.size() - 12000 : 0);
    }
  }
  std::string where;
  for (const auto& [phase, n] : killed_in) where += " " + phase + ":" + std::to_string(n);
  std::printf("%zu kills, by operation/state seen last:%s; %zu compared with the last acknowledged status\n", kills,
              where.c_str(), compared_with_ack);
  EXPECT_GE(compared_with_ack, kills / 2) << "too few restarts had an acknowledged status to compare with";
}

}  // namespace
}  // namespace ispars::test
