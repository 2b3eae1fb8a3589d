#pragma once
// The wait the daemon's background threads share (the fleet thread, the health watchdog, a
// rejoin's overlap): each waits at most a period at a time, and every wait ends at once on stop().

#include <chrono>
#include <condition_variable>
#include <mutex>

namespace ispars::server {

/// A stop flag with waits that end when it is raised; the fleet thread's wait also ends early on
/// wake() (the fleet changed, or the process stood still).
class StopSignal {
 public:
  /// Waits until `period` has passed, wake() was called since the last such wait returned, or
  /// stop(). False once stopped.
  bool wait_for(std::chrono::milliseconds period);
  /// Waits until `period` has passed or stop(), whatever wake() says. False once stopped.
  bool idle_for(std::chrono::milliseconds period);
  /// Ends the current (or the next) wait_for early.
  void wake();
  /// Ends every wait now and later.
  void stop();
  [[nodiscard]] bool stopped() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool stopped_ = false;
  bool woken_ = false;
};

}  // namespace ispars::server
