#include "ispars/roadmap_snapshot.hpp"

namespace ispars {

void RoadmapSnapshots::publish(const Roadmap& current) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (latest_->version() == current.version() && latest_->vertex_count() == current.vertex_count()) return;
  }
  auto copy = std::make_shared<const Roadmap>(current);  // copied outside the lock
  const std::lock_guard<std::mutex> lock(mutex_);
  latest_ = std::move(copy);
}

std::shared_ptr<const Roadmap> RoadmapSnapshots::latest() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

}  // namespace ispars
