#pragma once
// The inspection tasks other daemons published for the scenes they hold (ispars/tasks), kept
// after their publisher leaves: a daemon that takes a scene over builds the roadmap with the
// former owner's tasks (docs/fleet.md). Safe from many threads. Knows nothing of DDS entities.

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "ispars.h"
#include "ispars/service/inspection_task.hpp"

namespace ispars::server {

class TaskBoard {
 public:
  /// A task as a daemon published it (from the daemon it names: the reader checks). One that is
  /// out of bounds (index >= kMaxTasks, more than kMaxTaskPois POIs, a bad name, a POI not
  /// finite) is ignored and logged.
  void seen(const msg::SceneTask& task);

  /// Tasks held, every scene's, daemon's and generation's.
  [[nodiscard]] std::size_t size() const;

  /// The tasks of `scene`'s roadmap of `generation` as daemon `server` published them, in order,
  /// when the board holds all of them: indices 0 .. n-1 of that generation whose events (added,
  /// plus removed) are `events` and whose POIs number `task_pois` in all (if known). Nothing otherwise
  /// (some did not arrive). Two daemons' lists are kept apart: the two sides of a partition
  /// publish different tasks at one index.
  [[nodiscard]] std::optional<std::vector<service::InspectionTask>> tasks_of(
      const std::string& scene, const std::string& server, std::uint64_t generation, std::uint64_t events,
      std::optional<std::size_t> task_pois) const;

 private:
  struct Entry {
    std::uint64_t generation = 0;
    service::InspectionTask task;
  };
  mutable std::mutex mutex_;
  std::map<std::tuple<std::string, std::string, std::uint32_t>, Entry> tasks_;  // by (scene, server, index)
};

}  // namespace ispars::server
