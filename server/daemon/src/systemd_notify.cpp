#include "ispars/server/systemd_notify.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <string>

namespace ispars::server {

SystemdNotifier::SystemdNotifier() {
  std::uint64_t usec = 0;
  // > 0 only when WATCHDOG_USEC is set and WATCHDOG_PID, if set, is this process.
  if (sd_watchdog_enabled(0, &usec) > 0 && usec > 0) watchdog_period_ = std::chrono::microseconds(usec / 2);
}

void SystemdNotifier::ready(std::string_view status) const {
  const std::string message = "READY=1\nSTATUS=" + std::string(status);
  (void)sd_notify(0, message.c_str());
}

void SystemdNotifier::reloading() const { (void)sd_notify(0, "RELOADING=1"); }

void SystemdNotifier::stopping(std::string_view status) const {
  const std::string message = "STOPPING=1\nSTATUS=" + std::string(status);
  (void)sd_notify(0, message.c_str());
}

void SystemdNotifier::watchdog() const { (void)sd_notify(0, "WATCHDOG=1"); }

}  // namespace ispars::server
