#pragma once
// isparsd's configuration: a YAML file, then command-line flags over it. Each setting is declared
// once, with its key, bounds and doc (daemon_settings.hpp, and participant_options.hpp for the
// participant's), and listed once with its member (DaemonConfig::describe); the file's reader and
// writer (here) and the flags (daemon_flags.hpp) check each value as it arrives.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ispars/server/daemon_settings.hpp"
#include "ispars/wire/participant_options.hpp"

namespace ispars::server {

/// An address to listen on: an IPv4 address and a port (0: any free port).
struct ListenAddress {
  std::string host;
  int port = 0;
  bool operator==(const ListenAddress&) const = default;
};

/// Everything isparsd is configured with, file and flags merged. Each member is declared once
/// (describe; the declarations are daemon_settings.hpp's and participant_options.hpp's), and
/// its initialiser is its default.
struct DaemonConfig {
  std::filesystem::path data_dir = "/var/lib/ispars";            ///< Stored roadmaps, one directory per scene.
  std::filesystem::path scene_dir = "/usr/share/ispars/scenes";  ///< The only place scenes load from.
  /// How the daemon joins the domain: its id, profiles file and profile, DDS Security identity
  /// and lease (its `name` is the daemon's, set from server_id).
  wire::ParticipantOptions participant;
  std::uint32_t workers = 2;  ///< Build worker threads.
  /// Threads each build uses for its per-sample work (point check, chi); any count gives the
  /// same roadmap.
  std::uint32_t build_threads = 1;
  std::string log_level = "info";
  /// Where the log goes: empty for standard output (the journal under systemd), else this file,
  /// rotated at log_file_mb (4 older files kept) and reopened on SIGHUP.
  std::filesystem::path log_file;
  std::uint64_t log_file_mb = 64;
  /// Where the HTTP endpoint serving /metrics (Prometheus text) and /healthz listens ("ADDRESS:PORT"
  /// in the file and the flag); none: no endpoint. Port 0 takes any free port (the log names it).
  std::optional<ListenAddress> metrics;
  std::string server_id;                      ///< Unique on the domain; empty: HOST-PID.
  std::uint64_t max_samples = 50'000'000;     ///< Per build or extend request.
  std::uint64_t snapshot_compact_every = 64;  ///< Journal commits between compactions.
  std::vector<std::string> preload;           ///< Scenes to load at start.
  /// Requests each lane (quick, slow) holds waiting; past that a request is refused as busy.
  std::uint64_t request_queue = 256;
  /// MiB the roadmaps of all loaded scenes may be expected to hold together; 0: half of this
  /// machine's memory. A build or extend whose estimate does not fit is refused before it starts.
  std::uint64_t memory_budget_mb = 0;
  /// Milliseconds to listen for the other daemons on the domain before announcing, reloading
  /// stored roadmaps or claiming a scene (the fleet's ownership rule needs them all seen).
  std::uint32_t discovery_wait_ms = 1000;
  /// Mirror each loaded scene's roadmap (visualization_msgs/MarkerArray) and its last tour
  /// (nav_msgs/Path) to ROS 2 topics, in frame ros2_frame (docs/ros2.md).
  bool ros2 = false;
  std::string ros2_frame = "map";

  /// Every setting with its declaration, in the order `isparsd --help` lists them.
  static void describe(auto& self, auto&& field) {
    using namespace settings;
    field(kDataDir, self.data_dir);
    field(kSceneDir, self.scene_dir);
    field(wire::kDomain, self.participant.domain);
    field(kWorkers, self.workers);
    field(kBuildThreads, self.build_threads);
    field(wire::kProfileFile, self.participant.profile_file);
    field(wire::kProfileName, self.participant.profile_name);
    field(wire::kSecurity, self.participant.security);
    field(wire::kLease, self.participant.lease_seconds);
    field(kLogLevel, self.log_level);
    field(kServerId, self.server_id);
    field(kMaxSamples, self.max_samples);
    field(kCompactEvery, self.snapshot_compact_every);
    field(kPreload, self.preload);
    field(kRequestQueue, self.request_queue);
    field(kMemoryBudget, self.memory_budget_mb);
    field(kDiscoveryWait, self.discovery_wait_ms);
    field(kLogFile, self.log_file);
    field(kLogFileMb, self.log_file_mb);
    field(kMetrics, self.metrics);
    field(kRos2, self.ros2);
    field(kRos2Frame, self.ros2_frame);
  }
};

/// This machine's host name ("host" when it cannot be read).
[[nodiscard]] std::string host_name();

/// The memory budget in bytes: config.memory_budget_mb, or half of physical memory when 0.
[[nodiscard]] double memory_budget_bytes(const DaemonConfig& config);

/// Reads a config file. Throws InputError naming the file and key on an unknown key or a value
/// of the wrong type, out of its bounds, or against its rule (daemon_settings.hpp).
[[nodiscard]] DaemonConfig load_daemon_config(const std::filesystem::path& path);

/// The settings that cannot go together, each checked alone already: `ros2` with `security` (the
/// mirror's participant would need permissions for rt/ispars/ topics, which the keystore's
/// daemon grants do not give). Throws InputError naming both.
void check_together(const DaemonConfig& config);

/// The keys of the settings that differ between `running` and `fresh` and that a running daemon
/// takes only at a restart (each one declared needs_restart), in declaration order. A fresh
/// config without a server_id asks for the default the running one already holds.
[[nodiscard]] std::vector<std::string> changed_needing_restart(const DaemonConfig& running, DaemonConfig fresh);

/// `config` as a config file (`isparsd --print-config`): every setting, paths made absolute, an
/// unset listen address left out. Reading it back gives the same config.
[[nodiscard]] std::string to_yaml(const DaemonConfig& config);

/// Parses "ADDRESS:PORT"; throws InputError naming `source` and `field` when it is not one.
[[nodiscard]] ListenAddress parse_listen_address(const std::string& text, const std::string& source,
                                                 const std::string& field);

}  // namespace ispars::server
