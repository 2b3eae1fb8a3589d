#include "ispars/server/takeover_runner.hpp"

#include <utility>

namespace ispars::server {

bool TakeoverRunner::start(const std::string& scene, std::function<void()> work) {
  std::lock_guard lock(mutex_);
  reap();
  if (stopped_ || runs_.count(scene) > 0 || runs_.size() >= kMaxRunning) return false;
  auto done = std::make_shared<bool>(false);
  std::thread thread([this, done, work = std::move(work)] {
    work();
    std::lock_guard finished(mutex_);
    *done = true;
  });
  runs_.emplace(scene, Run{std::move(thread), std::move(done)});
  return true;
}

bool TakeoverRunner::running(const std::string& scene) const {
  std::lock_guard lock(mutex_);
  const auto it = runs_.find(scene);
  return it != runs_.end() && !*it->second.done;
}

void TakeoverRunner::reap() {
  for (auto it = runs_.begin(); it != runs_.end();) {
    if (!*it->second.done) {
      ++it;
      continue;
    }
    it->second.thread.join();  // returned already: its last step is setting `done`
    it = runs_.erase(it);
  }
}

void TakeoverRunner::stop() {
  std::map<std::string, Run> runs;
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
    runs = std::exchange(runs_, {});
  }
  for (auto& [scene, run] : runs) {
    if (run.thread.joinable()) run.thread.join();
  }
}

}  // namespace ispars::server
