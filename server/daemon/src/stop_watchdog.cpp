#include "ispars/server/stop_watchdog.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <memory>
#include <utility>

namespace ispars::server {

namespace {
std::atomic<const char*> current_stop_step{nullptr};
}  // namespace

void note_stop_step(const char* step) noexcept { current_stop_step.store(step); }

const char* stop_step() noexcept { return current_stop_step.load(); }

StopWatchdog::StopWatchdog(std::chrono::milliseconds deadline, Expiry on_expiry)
    : thread_([this, deadline, expiry = std::move(on_expiry)] {
        {
          std::unique_lock lock(mutex_);
          if (wake_.wait_for(lock, deadline, [this] { return disarmed_; })) return;
        }
        expiry(stop_step());
      }) {}

StopWatchdog::~StopWatchdog() {
  {
    std::lock_guard lock(mutex_);
    disarmed_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void arm_stop_watchdog() {
  // The logger itself, not the registry's name for it: the registry may be gone by then (the
  // process's static destructors).
  std::shared_ptr<spdlog::logger> logger = spdlog::default_logger();
  // Never deleted, so never disarmed (see the header); the process's end ends its thread.
  static StopWatchdog* const watchdog = new StopWatchdog(kStopDeadline, [logger](const char* step) {
    // The line is bounded too: the stuck thread may hold the log's mutex.
    std::thread([] {
      std::this_thread::sleep_for(std::chrono::seconds(1));
      ::_exit(kExitStopTimedOut);
    }).detach();
    logger->error(
        "the stop did not finish within {} s (waiting for {}); exiting with status {} without it (every "
        "commit is already on disk)",
        kStopDeadline.count(), step != nullptr ? step : "an unnamed step", kExitStopTimedOut);
    logger->flush();
    ::_exit(kExitStopTimedOut);
  });
  (void)watchdog;
}

}  // namespace ispars::server
