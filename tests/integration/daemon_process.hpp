#pragma once
// A real isparsd process for the integration tests, on an isolated domain, localhost only.

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

#include "ispars/client/client.hpp"

namespace ispars::test {

/// A DDS domain id no other test run is likely to use (random in 100..232).
int random_domain();

/// Writes procedural scenes NAME.yaml (tank towers with different seeds) into `dir`.
void write_test_scenes(const std::filesystem::path& dir, const std::vector<std::string>& names);

/// Client options for `domain`, with a generous timeout for loaded CI machines.
client::ClientOptions client_options(int domain);

class DaemonProcess {
 public:
  /// Starts isparsd and waits until a client sees its announcement (throws after 20 s).
  DaemonProcess(int domain, std::filesystem::path data_dir, std::filesystem::path scene_dir, std::string server_id,
                std::vector<std::string> extra_args = {});
  /// Stops it with SIGTERM if it still runs.
  ~DaemonProcess();
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  /// SIGTERM, then waits; returns the exit status (or -signal).
  int terminate();
  /// SIGKILL, then waits.
  void kill9();
  /// Whether the process is still running.
  bool alive();
  [[nodiscard]] const std::string& server_id() const { return server_id_; }
  /// The daemon's log so far.
  [[nodiscard]] std::string log() const;

 private:
  int wait_exit();
  pid_t pid_ = -1;
  int domain_;
  std::string server_id_;
  std::filesystem::path log_path_;
};

}  // namespace ispars::test
