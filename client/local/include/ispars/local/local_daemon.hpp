#pragma once
// A local isparsd child process (the service benchmark, the integration tests): started on a
// given domain with the built-in localhost-only profile, ready once a client sees its
// announcement.

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ispars/client/client.hpp"

namespace ispars::local {

/// A DDS domain id of 1, 5, ..., 97 (whose ports lie below Linux's ephemeral ones) that no other
/// test process on this machine holds: each process locks the domains it draws
/// (/tmp/ispars-test-domains/N.lock) until it exits.
int random_domain();

/// Writes procedural scenes NAME.yaml (tank towers with seeds 1, 2, ...) into `dir`.
void write_tank_tower_scenes(const std::filesystem::path& dir, const std::vector<std::string>& names);

/// Client options for `domain`, with a generous timeout for loaded machines.
client::ClientOptions local_client_options(int domain);

/// Runs deploy/security/make-keystore.sh (the script at `script`) into `dir` for `identities`
/// ("ROLE:NAME" each) and returns dir; throws with the script's output when it fails.
std::filesystem::path make_keystore(const std::string& script, const std::filesystem::path& dir,
                                    const std::vector<std::string>& identities);

class LocalDaemon {
 public:
  /// Starts `daemon_binary` and waits until a client sees its announcement (throws after
  /// `ready_within`: a daemon announces itself once its stored roadmaps are loaded).
  /// Its output goes to a log file beside data_dir.
  /// `probe_security`: the DDS Security identity the readiness probe uses (a secured daemon's
  /// announcement reaches only authenticated clients).
  /// `environment`: variables set in the daemon's process only ("NAME=VALUE" each).
  /// `command_prefix`: a command the daemon runs under (e.g. `ip netns exec NS`; its first word a
  /// full path), which must exec the daemon in its own process.
  /// `probe_profile_file`: the Fast DDS profile of the readiness probe (default: the daemon's
  /// --profile-file, else the built-in localhost profile).
  LocalDaemon(const std::string& daemon_binary, int domain, std::filesystem::path data_dir,
              std::filesystem::path scene_dir, std::string server_id, std::vector<std::string> extra_args = {},
              const std::string& probe_security = "", const std::vector<std::string>& environment = {},
              std::chrono::seconds ready_within = std::chrono::seconds(20),
              const std::vector<std::string>& command_prefix = {}, const std::string& probe_profile_file = "");
  /// Stops it with terminate() if it still runs.
  ~LocalDaemon();
  LocalDaemon(const LocalDaemon&) = delete;
  LocalDaemon& operator=(const LocalDaemon&) = delete;

  /// How long terminate() waits after SIGTERM, and kill9() after SIGKILL, before it gives up on
  /// the daemon: an orderly stop takes well under a second (a running build's current chunk and
  /// its commit, then the participant's deletion), and isparsd's own watchdog ends a stuck stop
  /// at 5 s (exit status 4), so this catches only a daemon whose watchdog could not run either.
  static constexpr std::chrono::seconds kStopDeadline{10};
  /// terminate()'s result when the daemon had not exited kStopDeadline after SIGTERM: every
  /// thread's stack (gdb, at most about 25 s) went into its log, then it was killed with SIGKILL.
  static constexpr int kStopTimedOut = -2000;

  /// SIGTERM, then waits up to kStopDeadline: the exit status (or -signal), or kStopTimedOut
  /// (said on stderr too).
  int terminate();
  /// SIGKILL, then waits up to kStopDeadline; false (said on stderr) when it still had not exited.
  bool kill9();
  /// Whether a terminate() or kill9() of this daemon (its destructor's included) ran out of time.
  [[nodiscard]] bool stop_timed_out() const { return stop_timed_out_; }
  /// Whether the process is still running.
  bool alive();
  /// Waits up to `limit` for the process to exit by itself: its exit status (or -signal), or
  /// nullopt when it still runs.
  std::optional<int> exit_within(std::chrono::milliseconds limit);
  [[nodiscard]] const std::string& server_id() const { return server_id_; }
  /// The daemon's log so far: its output, then the file it was told to log to (--log-file).
  [[nodiscard]] std::string log() const;
  [[nodiscard]] pid_t pid() const { return pid_; }

 private:
  // Forks and runs `args` (the program first) with the environment plus `environment`, its
  // output appended to log_path_.
  void spawn(std::vector<std::string> args, const std::vector<std::string>& environment);
  // Returns once the log says it serves (from byte `log_start` on) and `probe_options`' client
  // sees it; kills it and throws when it exits or is not seen within `ready_within`.
  void wait_until_serving(const client::ClientOptions& probe_options, std::size_t log_start,
                          std::chrono::seconds ready_within);

  pid_t pid_ = -1;
  bool stop_timed_out_ = false;
  int domain_;
  std::string server_id_;
  std::filesystem::path log_path_;
  std::filesystem::path own_log_path_;  // --log-file, when given
};

}  // namespace ispars::local
