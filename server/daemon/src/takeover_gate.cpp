#include "ispars/server/takeover_gate.hpp"

namespace ispars::server {

TakeoverGate::Held::Held(TakeoverGate& gate, std::string scene) : gate_(gate), scene_(std::move(scene)) {
  std::lock_guard lock(gate_.mutex_);
  gate_.held_.insert(scene_);
}

TakeoverGate::Held::~Held() {
  {
    std::lock_guard lock(gate_.mutex_);
    gate_.held_.erase(gate_.held_.find(scene_));
  }
  gate_.released_.notify_all();
}

bool TakeoverGate::wait(const std::string& scene, std::chrono::milliseconds at_most) const {
  std::unique_lock lock(mutex_);
  return released_.wait_for(lock, at_most, [&] { return held_.count(scene) == 0; });
}

}  // namespace ispars::server
