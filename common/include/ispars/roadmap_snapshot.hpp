#pragma once
// Consistent views of a roadmap under construction for any number of reader threads.
//
// The builder owns its roadmap and is its only writer; readers never touch it. After a batch
// the writer publishes an immutable copy, and a reader takes the latest copy, which stays valid
// and unchanged for as long as it holds it. (OMPL's SPARS let its solution thread read vertex
// data while construction reallocated it; here no reader can.)

#include <memory>
#include <mutex>

#include "ispars/roadmap.hpp"

namespace ispars {

/// Hands out the latest published roadmap. publish() and latest() are safe from any threads.
class RoadmapSnapshots {
 public:
  /// Publishes a copy of `current` (the writer's roadmap), unless it is the version already out.
  void publish(const Roadmap& current);
  /// The latest published roadmap (an empty one before the first publish); never changes.
  [[nodiscard]] std::shared_ptr<const Roadmap> latest() const;

 private:
  mutable std::mutex mutex_;
  std::shared_ptr<const Roadmap> latest_ = std::make_shared<const Roadmap>();
};

}  // namespace ispars
