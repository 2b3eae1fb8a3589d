// `ispars record`: a scene's roadmap saved as it grows, batch by batch, and optionally a tour of
// it, as an MCAP file of foxglove.SceneUpdate messages that Foxglove replays (client/record/).

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/record/mcap_writer.hpp"
#include "ispars/record/scene_update.hpp"
#include "ispars/record/scene_update_cursor.hpp"

namespace ispars::cli {
namespace {

std::atomic<bool> g_interrupted{false};

// The file's roadmap channel, fed from the replica through a cursor.
class RoadmapRecording {
 public:
  RoadmapRecording(record::McapWriter& mcap, std::uint16_t channel, std::string frame)
      : mcap_(mcap), channel_(channel), cursor_(record::SceneStyle{std::move(frame)}) {}
  // Writes what is new in the replica since the last call (all of it again after a snapshot).
  void write_changes(const client::RoadmapReplica& replica) {
    // The replica is copied only when it changed: a poll of an idle scene costs no copy.
    const Seen seen{replica.generation(), replica.version(), replica.snapshots_taken()};
    if (seen == seen_) return;
    seen_ = seen;
    if (auto update = cursor_.next(replica.roadmap(), seen.generation, seen.snapshots, record::now_ns())) {
      mcap_.write(channel_, record::now_ns(), update->dump());
    }
  }
  [[nodiscard]] const record::SceneStyle& style() const { return cursor_.style(); }
  [[nodiscard]] std::size_t vertices() const { return cursor_.vertices(); }
  [[nodiscard]] std::size_t edges() const { return cursor_.edges(); }

 private:
  struct Seen {
    std::uint64_t generation = 0, version = 0;
    std::size_t snapshots = 0;
    bool operator==(const Seen&) const = default;
  };
  record::McapWriter& mcap_;
  const std::uint16_t channel_;
  record::SceneUpdateCursor cursor_;
  Seen seen_;
};

class RecordCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("record", "save a roadmap as it grows, and a tour, as MCAP for Foxglove");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--out", out_, "the MCAP file to write (whole or not at all)")->required();
    cmd->add_flag("--until-idle", until_idle_, "stop when the scene has no job and the replica is current");
    cmd->add_option("--tour", tour_, "then ask the daemon for a tour of SECONDS and record it (0: none)")
        ->check(CLI::Range(0.0, 3600.0));
    cmd->add_option("--frame", frame_, "the frame_id of every entity (default map)");
    return cmd;
  }
  int run(client::Client& client) override {
    std::signal(SIGINT, [](int) { g_interrupted = true; });
    std::signal(SIGTERM, [](int) { g_interrupted = true; });
    (void)client.stats(scene_);  // fails clearly when the scene is not loaded anywhere
    record::McapWriter mcap(out_, "ispars record");
    const std::uint16_t schema = mcap.add_schema("foxglove.SceneUpdate", "jsonschema", record::scene_update_schema());
    RoadmapRecording roadmap(mcap, mcap.add_channel(schema, "/ispars/" + scene_ + "/roadmap", "json"), frame_);
    const std::uint16_t tour_channel = mcap.add_channel(schema, "/ispars/" + scene_ + "/tour", "json");
    client::RoadmapReplica replica(client, scene_);
    const bool retired = follow(client, replica, roadmap);
    std::size_t stops = 0;
    bool tour_failed = false;
    if (!retired && tour_ > 0.0 && !g_interrupted) {
      try {
        const client::Tour tour = client.tour(scene_, tour_, 1, {}).tour;
        const std::vector<Vec3>& path = tour.flown_path.empty() ? tour.waypoints : tour.flown_path;
        mcap.write(tour_channel, record::now_ns(), record::tour_update(path, roadmap.style(), record::now_ns()).dump());
        stops = path.size();
      } catch (const client::ClientError& e) {  // the roadmap recorded is kept: the file is finished
        std::cerr << "ispars: the tour was not recorded: " << e.what() << "\n";
        tour_failed = true;
      }
    }
    mcap.finish();
    std::cout << fmt::format("wrote {} messages to {}: {} vertices, {} edges{}\n", mcap.messages(), out_,
                             roadmap.vertices(), roadmap.edges(),
                             stops > 0 ? fmt::format(", a tour of {} stops", stops) : std::string());
    if (!retired) return tour_failed ? 1 : 0;
    std::cerr << fmt::format("ispars: the roadmap of scene '{}' was dropped or unloaded while recording\n", scene_);
    return 1;
  }

 private:
  // Records until interrupted, idle (--until-idle) or the roadmap is gone; true when it is gone.
  bool follow(client::Client& client, const client::RoadmapReplica& replica, RoadmapRecording& roadmap) const {
    while (!g_interrupted) {
      roadmap.write_changes(replica);
      if (replica.retirements() > 0) return true;
      if (until_idle_) {
        const auto s = client.latest_status(scene_);
        if (s && !client::busy(s->state) && replica.snapshots_taken() > 0) {
          const client::SceneStatus now = client.stats(scene_);
          if (replica.wait_for(now.generation, now.version, std::chrono::seconds(10))) break;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    roadmap.write_changes(replica);
    return false;
  }

  std::string scene_, out_, frame_ = "map";
  bool until_idle_ = false;
  double tour_ = 0.0;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_record_command() { return std::make_unique<RecordCommand>(); }

}  // namespace ispars::cli
