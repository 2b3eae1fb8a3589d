#pragma once
// Scenes being taken over from a daemon that left: loaded here, the former owner's work not yet
// resumed. For the few milliseconds between the two the scene's roadmap here is empty and idle;
// a request for it waits until the takeover has resumed the work, so no client reads that
// state (FleetTest.WhenTheOwnerIsKilled... once did: its wait_idle returned an empty roadmap).

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <set>
#include <string>

namespace ispars::server {

class TakeoverGate {
 public:
  /// How long a request waits at most (a takeover that hangs must not hold requests).
  static constexpr std::chrono::milliseconds kMaxWait{2000};

  /// Holds the requests for `scene` until the returned guard is gone.
  class Held {
   public:
    Held(TakeoverGate& gate, std::string scene);
    ~Held();
    Held(const Held&) = delete;
    Held& operator=(const Held&) = delete;

   private:
    TakeoverGate& gate_;
    std::string scene_;
  };
  [[nodiscard]] Held hold(const std::string& scene) { return Held(*this, scene); }

  /// Waits while `scene` is held, at most `at_most`; whether it is free now.
  bool wait(const std::string& scene, std::chrono::milliseconds at_most = kMaxWait) const;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable released_;
  std::multiset<std::string> held_;
};

}  // namespace ispars::server
