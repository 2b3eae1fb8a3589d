#include "ispars/server/stop_signal.hpp"

namespace ispars::server {

bool StopSignal::wait_for(std::chrono::milliseconds period) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, period, [this] { return stopped_ || woken_; });
  woken_ = false;
  return !stopped_;
}

bool StopSignal::idle_for(std::chrono::milliseconds period) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, period, [this] { return stopped_; });
  return !stopped_;
}

void StopSignal::wake() {
  {
    std::lock_guard lock(mutex_);
    woken_ = true;
  }
  changed_.notify_all();
}

void StopSignal::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  changed_.notify_all();
}

bool StopSignal::stopped() const {
  std::lock_guard lock(mutex_);
  return stopped_;
}

}  // namespace ispars::server
