// `ispars watch`: a live replica of a scene's roadmap, kept from its update stream until Ctrl-C,
// SIGTERM, the scene going idle (--until-idle) or its roadmap being dropped or unloaded. With
// --json: one JSON line each time the replica changes, and one at the end, for a pipe.

#include <fmt/format.h>

#include <atomic>
#include <csignal>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/roadmap/roadmap_json.hpp"

namespace ispars::cli {
namespace {

std::atomic<bool> g_interrupted{false};

// The replica as one JSON object: `event` ("replica" as it changes, "end" at the end).
nlohmann::json replica_json(const std::string& event, const std::string& scene, const client::RoadmapReplica& replica,
                            const Roadmap& g) {
  return {{"event", event},
          {"scene", scene},
          {"generation", replica.generation()},
          {"version", g.version()},
          {"vertices", g.vertex_count()},
          {"edges", g.edge_count()},
          {"snapshots", replica.snapshots_taken()},
          {"batches", replica.batches_applied()}};
}

// Whether the scene is idle and the replica has caught up with it.
bool caught_up(client::Client& client, const std::string& scene, const client::SceneStatus& s,
               const client::RoadmapReplica& replica) {
  if (client::busy(s.state) || replica.snapshots_taken() == 0) return false;
  const client::SceneStatus now = client.stats(scene);
  return replica.wait_for(now.generation, now.version, std::chrono::seconds(10));
}

class WatchCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("watch", "follow a roadmap live (a replica kept from update batches)");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--dump", dump_, "write the replica to FILE on exit (the ispars-lab build --out JSON)");
    cmd->add_flag("--until-idle", until_idle_, "exit when the scene has no job and the replica is current");
    cmd->add_flag("--json", json_, "JSON lines: one each time the replica changes, one at the end (no progress line)");
    return cmd;
  }
  int run(client::Client& client) override {
    std::signal(SIGINT, [](int) { g_interrupted = true; });
    std::signal(SIGTERM, [](int) { g_interrupted = true; });
    (void)client.stats(scene_);  // fails clearly when the scene is not loaded anywhere
    cli_app::Progress progress(!json_);
    client::RoadmapReplica replica(client, scene_);
    bool retired = false;
    std::uint64_t printed_generation = 0, printed_version = 0;
    const auto print_change = [&] {
      if (!json_ || (replica.generation() == printed_generation && replica.version() == printed_version)) return;
      const Roadmap now = replica.roadmap();
      printed_generation = replica.generation();
      printed_version = now.version();
      std::cout << replica_json("replica", scene_, replica, now).dump() << std::endl;
    };
    while (!g_interrupted) {
      const auto s = client.latest_status(scene_);
      if (s) progress(*s);
      print_change();
      if (replica.retirements() > 0) {  // dropped or unloaded: nothing left to follow
        retired = true;
        break;
      }
      if (until_idle_ && s && caught_up(client, scene_, *s, replica)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    progress.finish();
    print_change();
    const Roadmap g = replica.roadmap();
    if (json_) {
      nlohmann::json end = replica_json("end", scene_, replica, g);
      end["digest"] = fmt::format("{:016x}", roadmap_digest(g));
      end["retired"] = retired;
      std::cout << end.dump() << std::endl;
    } else {
      std::cout << fmt::format(
          "replica of {}: version {}, {} vertices, {} edges, digest {:016x} ({} snapshots, {} batches)\n", scene_,
          g.version(), g.vertex_count(), g.edge_count(), roadmap_digest(g), replica.snapshots_taken(),
          replica.batches_applied());
    }
    if (retired) return report_retired(client);
    if (!dump_.empty())
      cli_app::write_text(dump_, roadmap_file_json(scene_, replica.root(), replica.pois(), g, nullptr));
    return 0;
  }

 private:
  int report_retired(client::Client& client) const {
    const auto s = client.latest_status(scene_);
    const std::string what = !s                                         ? "dropped or unloaded"
                             : s->state == client::SceneState::unloaded ? "unloaded"
                             : s->state == client::SceneState::empty    ? "dropped"
                                                                        : "dropped or unloaded";
    std::cerr << fmt::format("ispars: the roadmap of scene '{}' was {} while watching{}\n", scene_, what,
                             dump_.empty() ? "" : "; nothing written to " + dump_);
    return 1;
  }

  std::string scene_, dump_;
  bool until_idle_ = false, json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_watch_command() { return std::make_unique<WatchCommand>(); }

}  // namespace ispars::cli
