#pragma once
// What every ispars-bench subcommand shares: a daemon of its own in a temporary directory, and
// the statistics it prints.

#include <stdlib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "ispars/client/wire_calls.hpp"
#include "ispars/local/local_daemon.hpp"

namespace ispars::bench {

using Clock = std::chrono::steady_clock;
using ispars::client::Client;
using ispars::local::LocalDaemon;

inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

inline double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

// A temporary working directory with the scenes, a data directory and a running daemon.
struct Bench {
  /// `daemon_identity`, `probe_identity`: DDS Security identity directories of the daemon and of
  /// its readiness probe (empty: no security).
  /// `scenes`: the scene directory (empty: two procedural tank towers, "tower" and "tower2").
  Bench(const std::string& daemon_binary, std::vector<std::string> extra = {}, const std::string& daemon_identity = "",
        const std::string& probe_identity = "", std::filesystem::path scenes = {}) {
    char pattern[] = "/tmp/ispars-bench-XXXXXX";
    dir = ::mkdtemp(pattern);
    const bool procedural = scenes.empty();
    scene_dir = procedural ? dir / "scenes" : std::move(scenes);
    if (procedural) ispars::local::write_tank_tower_scenes(scene_dir, {"tower", "tower2"});
    domain = ispars::local::random_domain();
    if (!daemon_identity.empty()) {
      extra.push_back("--security");
      extra.push_back(daemon_identity);
    }
    daemon_args = extra;
    probe = probe_identity;
    daemon = std::make_unique<local::LocalDaemon>(daemon_binary, domain, dir / "data", scene_dir, "bench",
                                                  std::move(extra), probe_identity);
  }
  /// Stops the daemon (SIGTERM) and starts it again on the same directories; returns once it
  /// announces itself (after loading what it stored: up to 10 minutes for a large store).
  void restart(const std::string& daemon_binary) {
    daemon.reset();
    daemon = std::make_unique<local::LocalDaemon>(daemon_binary, domain, dir / "data", scene_dir, "bench", daemon_args,
                                                  probe, std::vector<std::string>{}, std::chrono::seconds(600));
  }
  ~Bench() {
    daemon.reset();
    std::filesystem::remove_all(dir);
  }
  ispars::client::ClientOptions options() const {
    auto o = ispars::local::local_client_options(domain);
    o.timeout = std::chrono::seconds(120);
    o.participant.security = client_identity;
    return o;
  }
  std::filesystem::path dir;
  std::filesystem::path scene_dir;
  std::vector<std::string> daemon_args;
  std::string probe;
  std::string client_identity;  ///< what options() gives clients (empty: no security)
  int domain = 0;
  std::unique_ptr<local::LocalDaemon> daemon;
};

/// A process's /proc status field in KiB ("VmRSS:", "VmHWM:"); 0 when unknown.
inline std::size_t proc_status_kib(pid_t pid, const std::string& field) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(field, 0) == 0) return std::stoul(line.substr(field.size()));
  }
  return 0;
}

/// `ispars-bench grow`: see grow_bench.cpp.
nlohmann::json run_grow(const std::string& daemon_binary, const std::filesystem::path& scene_dir,
                        const std::string& scene, BuildRequest build, std::uint64_t samples, std::uint64_t step);

/// `ispars-bench peak`: see peak_bench.cpp.
nlohmann::json run_peak(const std::string& daemon_binary, std::uint64_t samples,
                        const std::vector<std::string>& methods);

/// `ispars-bench rtt`: see rtt_bench.cpp. `keystore_script` empty: without DDS Security only.
nlohmann::json run_rtt(const std::string& daemon_binary, int count, const std::string& keystore_script);
/// The raw ping-pong's echo server (a hidden subcommand `rtt` starts): answers pings from
/// `client_identity` with the reply `reply_hex` (serialized, as hex digits).
int run_echo(int domain, const std::string& security, const std::string& client_identity, const std::string& reply_hex);
/// A reply serialized as hex digits, decoded.
msg::Reply reply_from_hex(const std::string& hex);

}  // namespace ispars::bench
