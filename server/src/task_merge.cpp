#include "task_merge.hpp"

#include <algorithm>

namespace ispars::server {
namespace {

// The entry of `name` still held in `tasks`, or nullptr.
const InspectionTask* held_task(std::span<const InspectionTask> tasks, const std::string& name) {
  const auto it =
      std::find_if(tasks.begin(), tasks.end(), [&](const InspectionTask& t) { return t.name == name && !t.removed; });
  return it == tasks.end() ? nullptr : &*it;
}

bool ever_had(std::span<const InspectionTask> tasks, const std::string& name) {
  return std::any_of(tasks.begin(), tasks.end(), [&](const InspectionTask& t) { return t.name == name; });
}

}  // namespace

TaskMerge merge_tasks(std::span<const InspectionTask> mine, std::span<const InspectionTask> theirs) {
  TaskMerge merge;
  for (const InspectionTask& t : theirs) {
    if (t.removed) {
      const InspectionTask* held = held_task(mine, t.name);
      if (held && held->pois == t.pois && !held_task(theirs, t.name) &&
          std::find(merge.remove.begin(), merge.remove.end(), t.name) == merge.remove.end()) {
        merge.remove.push_back(t.name);
      }
    } else if (!ever_had(mine, t.name)) {
      merge.add.push_back(t);
    }
  }
  return merge;
}

}  // namespace ispars::server
