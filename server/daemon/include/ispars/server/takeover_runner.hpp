#pragma once
// Takeovers beside the fleet thread: each scene taken over on a thread of its own, so that the
// fleet thread keeps applying the rule (giving scenes up, announcing, rejoining) while a scene's
// file is read and its store opened, and a stop waits for the takeovers already running, not for
// every scene still to take over (issue 42: they ran one at a time on the fleet thread).

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace ispars::server {

/// Runs one takeover per scene at a time, at most kMaxRunning at once.
class TakeoverRunner {
 public:
  /// Takeovers running at once, at most: each reads a scene file and opens a store.
  static constexpr std::size_t kMaxRunning = 4;

  TakeoverRunner() = default;
  ~TakeoverRunner() { stop(); }
  TakeoverRunner(const TakeoverRunner&) = delete;
  TakeoverRunner& operator=(const TakeoverRunner&) = delete;

  /// Runs `work` on a thread of its own, unless a takeover of `scene` still runs, kMaxRunning
  /// run, or stop() was called; whether it was started. `work` must not throw.
  bool start(const std::string& scene, std::function<void()> work);
  /// Whether a takeover of `scene` was started and has not finished.
  [[nodiscard]] bool running(const std::string& scene) const;
  /// Starts no more, and waits for those running (the daemon's stop).
  void stop();

 private:
  struct Run {
    std::thread thread;
    std::shared_ptr<bool> done;  // set under mutex_ when the work returned
  };
  void reap();  // under mutex_: joins the finished ones

  mutable std::mutex mutex_;
  std::map<std::string, Run> runs_;
  bool stopped_ = false;
};

}  // namespace ispars::server
