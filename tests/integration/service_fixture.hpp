#pragma once
// The fixture of the service integration tests: a scene directory of four small scenes, daemons
// started on one random domain (localhost only), and the helpers the tests share.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "ispars/client/client.hpp"
#include "ispars/client/wire_calls.hpp"
#include "ispars/local/local_daemon.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/wire/participant.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::test {

using client::BuildArgs;
using DaemonProcess = local::LocalDaemon;
using local::random_domain;
inline const auto client_options = local::local_client_options;
using client::Client;
using client::ClientError;
using client::make_change;
using client::make_query;
using client::SceneState;
using client::SceneStatus;
using client::Tour;

inline constexpr auto kLong = std::chrono::seconds(120);
/// The participant lease of the secured fault tests' daemons and clients (their profiles set it):
/// shorter than the built-in secured default (wire::kSecureLeaseSeconds, 20 s), which a test of
/// what follows a drop need not wait out, and as long as StallTest's, which passes with it.
inline constexpr std::chrono::seconds kSecuredTestLease{8};
// The largest memory budget a daemon accepts (1 PiB), for tests that start builds of millions of
// samples only to stop them early: the budget would refuse them (rightly) before they start.
inline constexpr const char* kNoBudget = "1073741824";

class ServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = random_domain();
    scene_dir_ = dir_.path() / "scenes";
    local::write_tank_tower_scenes(scene_dir_, {"s0", "s1", "s2", "s3"});
  }
  // A failed test shows the end of each daemon's log: what a rare failure in CI leaves to read.
  void TearDown() override {
    if (HasFailure()) print_daemon_log_tails(dir_.path(), 40);
  }
  std::unique_ptr<DaemonProcess> start(const std::string& id, std::vector<std::string> extra = {}) {
    return std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id), scene_dir_, id,
                                           std::move(extra));
  }
  TempDir dir_;
  int domain_ = 0;
  std::filesystem::path scene_dir_;
};

// The daemons holding `scene`, as their announcements say.
/// What daemon `server`'s entry in the scenes list notes about `scene` (empty when none).
inline std::string note_of(Client& client, const std::string& scene, const std::string& server) {
  for (const auto& e : client.list_scenes()) {
    if (e.scene == scene && e.server_id == server) return e.note;
  }
  return "";
}

inline std::vector<std::string> holders(Client& client, const std::string& scene) {
  std::vector<std::string> out;
  for (const auto& d : client.daemons()) {
    if (std::find(d.loaded.begin(), d.loaded.end(), scene) != d.loaded.end()) {
      out.push_back(d.server_id);
    }
  }
  return out;
}

// "s0".."s3" (built by appending: GCC 12 warns falsely on "s" + std::to_string(n)).
/// The port the daemon's log names for its metrics endpoint on `address`; -1 when it names none.
/// (No std::regex: GCC 12 warns inside <regex> in the sanitizer build, and warnings are errors.)
inline int metrics_port(const std::string& log, const std::string& address = "127.0.0.1") {
  const std::string before = "metrics on http://" + address + ":";
  const auto at = log.find(before);
  if (at == std::string::npos) return -1;
  const auto digits = at + before.size();
  const auto end = log.find("/metrics", digits);
  if (end == std::string::npos || end == digits || end - digits > 5) return -1;
  const std::string port = log.substr(digits, end - digits);
  if (port.find_first_not_of("0123456789") != std::string::npos) return -1;
  return std::stoi(port);
}

inline std::string scene_name(unsigned n) {
  std::string name = "s";
  name += std::to_string(n);
  return name;
}

inline BuildArgs ispars_build(std::uint64_t samples, std::uint64_t seed = 1, bool replace = false) {
  BuildArgs a;
  a.method = BuildMethod::ispars;
  a.samples = samples;
  a.seed = seed;
  a.replace = replace;
  return a;
}

// A built scene, as most service tests start: `scene` loaded, built with `args`, and waited for.
// The status it settled in; the test fails at once unless that is idle with every sample.
inline SceneStatus load_and_build(Client& client, const std::string& scene, const BuildArgs& args) {
  client.load(scene);
  client.build(scene, args);
  SceneStatus status = client.wait_idle(scene, {}, kLong);
  EXPECT_EQ(status.state, SceneState::idle) << scene << ": " << status.last_error;
  EXPECT_EQ(status.samples_done, args.samples) << scene;
  return status;
}

// The status of `scene` once daemon `server` serves it idle: asked again while the scene moves
// between daemons (the new owner named a moment before it claims the scene: "not loaded on daemon
// b"; another daemon still holding it). Each refusal's message goes to `refusals` if given. The
// last status read (its server_id tells a test that it never came).
inline SceneStatus idle_on(Client& client, const std::string& scene, const std::string& server,
                           std::chrono::milliseconds timeout, std::vector<std::string>* refusals = nullptr) {
  SceneStatus last;
  (void)eventually(
      [&] {
        try {
          last = client.wait_idle(scene, {}, kLong);
          return last.server_id == server;
        } catch (const ClientError& e) {
          if (refusals) refusals->push_back(e.what());
          return false;
        }
      },
      timeout, "daemon " + server + " serves " + scene, std::chrono::milliseconds(100));
  return last;
}

// The roadmap an uninterrupted in-process build of `samples` gives: the reference for the daemon.
inline std::uint64_t reference_digest(const std::filesystem::path& scene_file, std::uint64_t samples,
                                      std::uint64_t seed, BuildMethod method = BuildMethod::ispars,
                                      double stretch_slack = 0.0, std::uint64_t stretch_slack_after = 0) {
  const planning::Scene scene = planning::Scene::load(scene_file);
  planning::BuildOptions options;
  options.seed = seed;
  options.stretch_slack = stretch_slack;
  options.stretch_slack_after = stretch_slack_after;
  const auto builder = planning::make_roadmap_builder(method, scene, options);
  builder->extend(samples);
  return roadmap_digest(builder->roadmap());
}

}  // namespace ispars::test
