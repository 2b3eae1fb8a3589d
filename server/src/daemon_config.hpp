#pragma once
// isparsd's configuration: a YAML file, then command-line flags over it. Each setting is declared
// once, with its key, bounds and doc, in daemon_settings.hpp; the file's reader (here) and the
// flags (daemon_flags.hpp) check each value as it arrives.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ispars::server {

/// An address to listen on: an IPv4 address and a port (0: any free port).
struct ListenAddress {
  std::string host;
  int port = 0;
  bool operator==(const ListenAddress&) const = default;
};

/// Everything isparsd is configured with, file and flags merged.
struct DaemonConfig {
  std::filesystem::path data_dir = "/var/lib/ispars";            ///< Stored roadmaps, one directory per scene.
  std::filesystem::path scene_dir = "/usr/share/ispars/scenes";  ///< The only place scenes load from.
  int domain = 0;                                                ///< DDS domain id.
  unsigned workers = 2;                                          ///< Build worker threads.
  /// Threads each build uses for its per-sample work (point check, chi); any count gives the
  /// same roadmap.
  unsigned build_threads = 1;
  std::string profile_file;  ///< Fast DDS XML profiles; empty: built-in localhost-only settings.
  std::string profile_name = "ispars";
  /// A DDS Security identity directory (deploy/security/make-keystore.sh); empty: no security.
  std::string security;
  /// The participant's lease in seconds with the built-in settings; 0: 3, or 20 under security.
  unsigned lease_s = 0;
  std::string log_level = "info";
  /// Where the log goes: empty for standard output (the journal under systemd), else this file,
  /// rotated at log_file_mb (4 older files kept) and reopened on SIGHUP.
  std::filesystem::path log_file;
  std::uint64_t log_file_mb = 64;
  /// Where the HTTP endpoint serving /metrics (Prometheus text) and /healthz listens ("ADDRESS:PORT"
  /// in the file and the flag); none: no endpoint. Port 0 takes any free port (the log names it).
  std::optional<ListenAddress> metrics;
  std::string server_id;                    ///< Unique on the domain; empty: HOST-PID.
  std::uint64_t max_samples = 50'000'000;   ///< Per build or extend request.
  std::size_t snapshot_compact_every = 64;  ///< Journal commits between compactions.
  std::vector<std::string> preload;         ///< Scenes to load at start.
  /// Requests each lane (quick, slow) holds waiting; past that a request is refused as busy.
  std::size_t request_queue = 256;
  /// MiB the roadmaps of all loaded scenes may be expected to hold together; 0: half of this
  /// machine's memory. A build or extend whose estimate does not fit is refused before it starts.
  std::uint64_t memory_budget_mb = 0;
  /// Milliseconds to listen for the other daemons on the domain before announcing, reloading
  /// stored roadmaps or claiming a scene (the fleet's ownership rule needs them all seen).
  std::uint32_t discovery_wait_ms = 1000;
};

/// This machine's host name ("host" when it cannot be read).
[[nodiscard]] std::string host_name();

/// The memory budget in bytes: config.memory_budget_mb, or half of physical memory when 0.
[[nodiscard]] double memory_budget_bytes(const DaemonConfig& config);

/// Reads a config file. Throws InputError naming the file and key on an unknown key or a value
/// of the wrong type, out of its bounds, or against its rule (daemon_settings.hpp).
[[nodiscard]] DaemonConfig load_daemon_config(const std::filesystem::path& path);

/// Parses "ADDRESS:PORT"; throws InputError naming `source` and `field` when it is not one.
[[nodiscard]] ListenAddress parse_listen_address(const std::string& text, const std::string& source,
                                                 const std::string& field);

}  // namespace ispars::server
