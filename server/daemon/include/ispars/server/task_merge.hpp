#pragma once
// The inspection tasks a daemon that gave a scene up (the losing side of a partition, say)
// changed, carried into the winner's roadmap of the same lineage (docs/fleet.md). Pure.

#include <span>
#include <string>
#include <vector>

#include "ispars/service/inspection_task.hpp"

namespace ispars::server {

/// What the winner does to carry the loser's task changes: the tasks to add, then the names to
/// remove. Empty when the loser changed nothing the winner lacks.
struct TaskMerge {
  std::vector<service::InspectionTask> add;
  std::vector<std::string> remove;
  [[nodiscard]] bool empty() const { return add.empty() && remove.empty(); }
};

/// `mine`, the winner's task list, and `theirs`, the loser's (each as the store keeps it: one
/// entry per task added, flagged when removed). A task the loser holds and the winner never had
/// is added (with the loser's POIs); a task the loser removed that the winner still holds with
/// the same POIs is removed. A task the winner removed stays removed, and one it holds under a
/// name the loser used for other POIs is kept: the winner's acknowledged change stands.
[[nodiscard]] TaskMerge merge_tasks(std::span<const service::InspectionTask> mine,
                                    std::span<const service::InspectionTask> theirs);

}  // namespace ispars::server
