#pragma once
// isparsd's stop watchdog. A stop (SIGTERM, SIGINT) must never hang: once the signal is received,
// a thread of its own waits kStopDeadline for the process to end, and ends it otherwise, naming
// the step the stop was waiting for. A Fast DDS 2.9.1 event-thread deadlock (eProsima/Fast-DDS
// #6502: a participant's lease expiring while a reply route's DataWriter was deleted) once left a
// daemon that had received SIGTERM running for good.

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace ispars::server {

/// How long an orderly stop may take, from the signal to the end of the process. A stop waits
/// for running requests, for each running build's current chunk (at most about half a second of
/// work, then its commit) and for the participant's deletion: 0.1 to 0.25 s measured, idle or
/// with a build running, so 5 s is far past any stop that is not stuck. Ending a stop at the
/// deadline loses nothing committed: every commit is journaled and fsync'ed before it is
/// acknowledged (CrashTest kills the daemon at 50 moments and loses none), and an interrupted
/// job is resumed at the next start.
inline constexpr std::chrono::seconds kStopDeadline{5};

/// isparsd's exit status when its stop did not finish within kStopDeadline (docs/operations.md).
inline constexpr int kExitStopTimedOut = 4;

/// Names the step a stop is in now, for the watchdog's line: a string literal (only the pointer
/// is kept). Any thread.
void note_stop_step(const char* step) noexcept;
/// The step last named, or nullptr.
[[nodiscard]] const char* stop_step() noexcept;

/// Calls `on_expiry(stop_step())` on a thread of its own once `deadline` has passed, unless it is
/// destroyed first.
class StopWatchdog {
 public:
  using Expiry = std::function<void(const char* step)>;
  StopWatchdog(std::chrono::milliseconds deadline, Expiry on_expiry);
  /// Disarms it (waits for on_expiry if it runs now).
  ~StopWatchdog();
  StopWatchdog(const StopWatchdog&) = delete;
  StopWatchdog& operator=(const StopWatchdog&) = delete;

 private:
  std::mutex mutex_;
  std::condition_variable wake_;
  bool disarmed_ = false;
  std::thread thread_;
};

/// Arms the daemon's watchdog at the start of its stop. It is never disarmed: it guards the
/// process's exit too (Fast DDS's static factory goes last). On expiry it logs one line naming
/// the step, flushes the log and _exit()s with kExitStopTimedOut.
void arm_stop_watchdog();

}  // namespace ispars::server
