#pragma once
// Inspection tasks: named sets of POIs added to a scene's built roadmap at run time, and the
// rules a task must meet before anything is changed for it.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::service {

/// A named set of POIs added to a built roadmap. POI ids only append: a task's POIs take the ids
/// after the scene's own and the earlier tasks', in order, and keep them. A removed task keeps
/// its POIs' ids (and the roadmap keeps seeing them), but they leave every target set, and its
/// name is free again.
struct InspectionTask {
  std::string name;
  std::vector<Vec3> pois;
  bool removed = false;
};

/// At most this many POIs in one task.
inline constexpr std::size_t kMaxTaskPois = 5000;
/// At most this many tasks on one scene.
inline constexpr std::size_t kMaxTasks = 64;
/// A task's POI lies on the structure: within this distance (m) of the mesh's surface.
inline constexpr double kTaskPoiSurfaceTolerance = 0.01;

/// Whether `name` may name a task: 1 to 64 of A-Z a-z 0-9 _ - . not starting with '.'.
[[nodiscard]] bool valid_task_name(std::string_view name);

/// Checks `task` before it is added to `scene` (the scene with `tasks`' POIs). Throws InputError
/// (file "request") naming the field at fault: task.name (its form, or a task of that name
/// exists and is not removed), task.pois (none, more than kMaxTaskPois), task (the scene holds
/// kMaxTasks tasks, removed ones included: their POIs keep their ids), or task.pois[i] (not finite, outside the mesh's
/// bounding box grown by kTaskPoiSurfaceTolerance, or farther than that from its surface).
void check_task(const planning::Scene& scene, std::span<const InspectionTask> tasks, const InspectionTask& task);

/// `count` POIs uniform by area on `scene`'s surface from `seed` alone, with the scene's own
/// sampling rules (ground triangles skipped when its POIs skip them). Throws InputError
/// (task.sample) when `count` is 0 or above kMaxTaskPois.
[[nodiscard]] std::vector<Vec3> sample_task_pois(const planning::Scene& scene, std::size_t count, std::uint64_t seed);

/// One task's POIs on a roadmap.
struct TaskCoverage {
  std::string name;
  std::size_t first_poi = 0;  ///< Its POIs are ids first_poi .. first_poi + poi_count - 1.
  std::size_t poi_count = 0;
  std::size_t covered = 0;       ///< Seen by some vertex.
  std::size_t covered_root = 0;  ///< Seen by some vertex in the root's (vertex 0's) component.
};

/// Each task's coverage on `roadmap`, whose first `scene_pois` POIs are the scene's own; removed
/// tasks are left out.
[[nodiscard]] std::vector<TaskCoverage> task_coverage(const Roadmap& roadmap, std::size_t scene_pois,
                                                      std::span<const InspectionTask> tasks);

/// The POIs of task `name` that a vertex in the root's component of `roadmap` sees: a tour's
/// targets for that task. Throws InputError (file "request", field "task") when no task (not
/// removed) has that name, or the roadmap sees none of its POIs from the root's component.
[[nodiscard]] std::vector<PoiId> task_targets(const Roadmap& roadmap, std::size_t scene_pois,
                                              std::span<const InspectionTask> tasks, const std::string& name);

/// The POIs a vertex in the root's component of `roadmap` sees, but those of removed tasks: a
/// tour's targets when none are named. Empty when no task is removed (every such POI is a
/// target); throws InputError (field "targets") when removed tasks' POIs are the only ones seen.
[[nodiscard]] std::vector<PoiId> live_targets(const Roadmap& roadmap, std::size_t scene_pois,
                                              std::span<const InspectionTask> tasks);

/// The index in `tasks` of the task named `name` that is not removed. Throws InputError (file
/// "request", field "task") when there is none, saying so when it was removed already.
[[nodiscard]] std::size_t live_task(std::span<const InspectionTask> tasks, const std::string& name);

/// All tasks' POIs (removed tasks' too), in id order (the ids after the scene's own).
[[nodiscard]] std::vector<Vec3> task_pois(std::span<const InspectionTask> tasks);

}  // namespace ispars::service
