#include "ispars/server/task_merge.hpp"

#include <algorithm>

namespace ispars::server {
namespace {

// The entry of `name` still held in `tasks`, or nullptr.
const service::InspectionTask* held_task(std::span<const service::InspectionTask> tasks, const std::string& name) {
  const auto it = std::find_if(tasks.begin(), tasks.end(),
                               [&](const service::InspectionTask& t) { return t.name == name && !t.removed; });
  return it == tasks.end() ? nullptr : &*it;
}

bool ever_had(std::span<const service::InspectionTask> tasks, const std::string& name) {
  return std::any_of(tasks.begin(), tasks.end(), [&](const service::InspectionTask& t) { return t.name == name; });
}

}  // namespace

TaskMerge merge_tasks(std::span<const service::InspectionTask> mine, std::span<const service::InspectionTask> theirs) {
  TaskMerge merge;
  for (const service::InspectionTask& t : theirs) {
    if (t.removed) {
      const service::InspectionTask* held = held_task(mine, t.name);
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
