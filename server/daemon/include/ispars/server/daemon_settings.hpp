#pragma once
// Every setting of isparsd declared once, as ispars_params declares a parameter: its name (the
// config file's key; the flag is the key with dashes, plus an older alias for two), its bounds,
// one line of doc and whether a running daemon takes a change on SIGHUP or only at a restart.
// DaemonConfig::describe (daemon_config.hpp) lists them with the member each sets; the config
// file's reader and writer, the flags, the checks and `isparsd --help` all walk that list, so a
// setting cannot be read one way and checked another. The participant's own settings (domain,
// profiles, security, lease) are wire::ParticipantOptions', declared in participant_options.hpp.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/params/input_error.hpp"

#include "ispars/params/spec.hpp"
#include "ispars/params/text_spec.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"

namespace ispars::server {

/// An ADDRESS:PORT to listen on, or none (parse_listen_address, daemon_config.hpp).
struct AddressSpec {
  std::string_view name;
  std::string_view doc;
  bool needs_restart = true;
};

std::string log_level_rule(const std::string& level);
std::string log_file_rule(const std::string& file);
std::string memory_budget_rule(std::uint64_t mib);
std::string ros2_frame_rule(const std::string& frame);

namespace settings {
using params::Lower;
inline constexpr params::TextSpec kDataDir{"data_dir", "where roadmaps are stored", 4096, true, true};
inline constexpr params::TextSpec kSceneDir{"scene_dir", "the only directory scenes are loaded from", 4096, true, true};
inline constexpr params::Spec<std::uint32_t> kWorkers{"workers", 1, 64, "build worker threads", Lower::closed, true};
inline constexpr params::Spec<std::uint32_t> kBuildThreads{
    "build_threads", 1, 64, "threads each build uses (the roadmap is the same for any count)", Lower::closed, true};
inline constexpr params::TextSpec kLogLevel{
    "log_level", "trace, debug, info, warn, error, critical or off", 16, false, false, &log_level_rule};
inline constexpr params::TextSpec kServerId{"server_id", "this daemon's unique id on the domain (default HOST-PID)", 64,
                                            false, true};
inline constexpr params::Spec<std::uint64_t> kMaxSamples{
    "max_samples", 1, kSamples.max, "largest build or extend a request may ask for", Lower::closed, true};
inline constexpr params::Spec<std::uint64_t> kCompactEvery{"snapshot_compact_every",
                                                           1,
                                                           1'000'000'000,
                                                           "journal commits between compacted snapshots",
                                                           Lower::closed,
                                                           true,
                                                           nullptr,
                                                           "compact_every"};
inline constexpr params::ListSpec kPreload{
    "preload", "scenes to load at start (stored roadmaps load anyway)", 1024, 256, true, "load"};
inline constexpr params::Spec<std::uint64_t> kRequestQueue{
    "request_queue", 1,   100'000, "requests each lane (quick, slow) holds waiting before it answers busy",
    Lower::closed,   true};
inline constexpr params::Spec<std::uint64_t> kMemoryBudget{
    "memory_budget_mb",
    0,
    std::uint64_t{1} << 30,
    "MiB all loaded roadmaps may be expected to hold, 0 for half of RAM; builds past it are refused",
    Lower::closed,
    true,
    &memory_budget_rule};
inline constexpr params::Spec<std::uint32_t> kDiscoveryWait{
    "discovery_wait_ms", 100, 60'000, "how long to listen for the other daemons before claiming scenes",
    Lower::closed,       true};
inline constexpr params::TextSpec kLogFile{
    "log_file",    "log to this file, rotated by size and reopened on SIGHUP (default: stdout)", 4096, true, false,
    &log_file_rule};
inline constexpr params::Spec<std::uint64_t> kLogFileMb{
    "log_file_mb", 1, 100'000, "MiB a log file reaches before it is rotated", Lower::closed, false};
inline constexpr params::Spec<bool> kRos2{
    "ros2",        false, true, "mirror each scene's roadmap and last tour to ROS 2 topics (rt/ispars/SCENE/...)",
    Lower::closed, true};
inline constexpr params::TextSpec kRos2Frame{
    "ros2_frame", "the frame_id of the ROS 2 markers and paths (default map)", 256, false, true, &ros2_frame_rule};
inline constexpr AddressSpec kMetrics{
    "metrics",
    "ADDRESS:PORT serving /metrics (Prometheus) and /healthz over HTTP, e.g. 127.0.0.1:9464 (default: none)"};
}  // namespace settings

/// `text` read as `spec` says, or InputError naming `source` and `field` (a key or a flag).
template <class T>
T checked_number(const params::Spec<T>& spec, const std::string& text, const std::string& source,
                 const std::string& field) {
  params::Parsed<T> parsed = params::parse(spec, text);
  if (!parsed.problem.empty()) throw params::InputError(source, field, std::move(parsed.problem));
  return parsed.value;
}

/// `text` checked as `spec` says (a path resolved against `base` when it is relative), or
/// InputError naming `source` and `field`.
[[nodiscard]] std::string checked_text(const params::TextSpec& spec, const std::string& text,
                                       const std::filesystem::path& base, const std::string& source,
                                       const std::string& field);

/// `items` checked as `spec` says, or InputError naming `source` and `field`.
[[nodiscard]] std::vector<std::string> checked_list(const params::ListSpec& spec, std::vector<std::string> items,
                                                    const std::string& source, const std::string& field);

}  // namespace ispars::server
