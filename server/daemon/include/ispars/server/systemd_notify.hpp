#pragma once
// The daemon's side of systemd's service protocol (sd_notify(3)): READY once it serves, RELOADING
// around a SIGHUP, STOPPING when it stops, and WATCHDOG pings while it is healthy. Each call does
// nothing when the daemon was not started by systemd (no NOTIFY_SOCKET).

#include <chrono>
#include <optional>
#include <string_view>

namespace ispars::server {

/// The service manager's notification socket, as the environment names it.
class SystemdNotifier {
 public:
  /// Reads NOTIFY_SOCKET and the watchdog settings (WATCHDOG_USEC, WATCHDOG_PID) once.
  SystemdNotifier();

  /// READY=1 with a one-line STATUS.
  void ready(std::string_view status) const;
  /// RELOADING=1 (before a reload), then ready() again.
  void reloading() const;
  /// STOPPING=1 with a one-line STATUS.
  void stopping(std::string_view status) const;
  /// WATCHDOG=1.
  void watchdog() const;
  /// How often to ping: half the watchdog timeout the manager set; nullopt when it set none.
  [[nodiscard]] std::optional<std::chrono::microseconds> watchdog_period() const { return watchdog_period_; }

 private:
  std::optional<std::chrono::microseconds> watchdog_period_;
};

}  // namespace ispars::server
