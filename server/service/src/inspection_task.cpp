#include "ispars/service/inspection_task.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/poi_sampling.hpp"
#include "ispars/service/scene_catalog.hpp"
#include "request_input.hpp"

namespace ispars::service {

bool valid_task_name(std::string_view name) { return valid_scene_name(name); }  // the same rule

namespace {

// The POIs some vertex of a roadmap sees (all), and some vertex in the root's component (root).
struct Cover {
  std::vector<std::uint64_t> all, root;

  explicit Cover(const Roadmap& roadmap) : all(poi_words(roadmap.poi_count())), root(all.size()) {
    const VertexId root_component = roadmap.vertex_count() > 0 ? roadmap.component(0) : 0;
    for (VertexId v = 0; v < roadmap.vertex_count(); ++v) {
      const PoiBits bits = roadmap.visible(v);
      const bool in_root = roadmap.component(v) == root_component;
      for (std::size_t w = 0; w < all.size(); ++w) {
        all[w] |= bits[w];
        if (in_root) root[w] |= bits[w];
      }
    }
  }
  static bool has(const std::vector<std::uint64_t>& bits, std::size_t id) {
    return (bits[id / 64] >> (id % 64) & 1U) != 0;
  }
};

// The first POI id of each task.
std::vector<std::size_t> first_ids(std::size_t scene_pois, std::span<const InspectionTask> tasks) {
  std::vector<std::size_t> first;
  for (const InspectionTask& t : tasks) {
    first.push_back(scene_pois);
    scene_pois += t.pois.size();
  }
  return first;
}

std::string shown_name(std::string_view name) {
  std::string shown(name.substr(0, 80));
  for (char& c : shown) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return shown + (name.size() > 80 ? "..." : "");
}

void check_poi(const planning::Scene& scene, const Aabb& box, const Vec3& p, std::size_t i) {
  const std::string field = fmt::format("task.pois[{}]", i);
  if (!p.allFinite()) throw params::InputError(kRequest, field, "is not a finite point");
  if (!box.contains(p)) {
    throw params::InputError(
        kRequest, field,
        fmt::format("({:.3f}, {:.3f}, {:.3f}) is outside the structure's box ({:.3f}, {:.3f}, {:.3f}) to "
                    "({:.3f}, {:.3f}, {:.3f})",
                    p.x(), p.y(), p.z(), box.min.x(), box.min.y(), box.min.z(), box.max.x(), box.max.y(), box.max.z()));
  }
  const double d = scene.collision().distance_to_surface(p);
  if (d > kTaskPoiSurfaceTolerance) {
    throw params::InputError(
        kRequest, field,
        fmt::format("({:.3f}, {:.3f}, {:.3f}) is {:.3f} m from the structure's surface; a POI lies on "
                    "it (within {} m)",
                    p.x(), p.y(), p.z(), d, kTaskPoiSurfaceTolerance));
  }
}

}  // namespace

void check_task(const planning::Scene& scene, std::span<const InspectionTask> tasks, const InspectionTask& task) {
  if (!valid_task_name(task.name)) {
    throw params::InputError(kRequest, "task.name",
                             fmt::format("'{}' is not a task name (1-64 of A-Z a-z 0-9 _ - ., not starting with '.')",
                                         shown_name(task.name)));
  }
  for (const InspectionTask& t : tasks) {
    if (t.name == task.name && !t.removed) {
      throw params::InputError(kRequest, "task.name", fmt::format("a task '{}' exists already", t.name));
    }
  }
  if (tasks.size() >= kMaxTasks) {
    throw params::InputError(
        kRequest, "task",
        fmt::format("the scene holds {} tasks, the most it may (removed tasks count: their POIs keep "
                    "their ids until the roadmap is dropped)",
                    tasks.size()));
  }
  if (task.pois.empty()) throw params::InputError(kRequest, "task.pois", "a task has at least one POI");
  if (task.pois.size() > kMaxTaskPois) {
    throw params::InputError(kRequest, "task.pois",
                             fmt::format("{} POIs; a task has at most {}", task.pois.size(), kMaxTaskPois));
  }
  // The mesh's box grown by the tolerance: a point sampled on a top face may lie a rounding above it.
  Aabb box = scene.mesh().bounds();
  box.min.array() -= kTaskPoiSurfaceTolerance;
  box.max.array() += kTaskPoiSurfaceTolerance;
  for (std::size_t i = 0; i < task.pois.size(); ++i) check_poi(scene, box, task.pois[i], i);
}

std::vector<Vec3> sample_task_pois(const planning::Scene& scene, std::size_t count, std::uint64_t seed) {
  if (count == 0 || count > kMaxTaskPois) {
    throw params::InputError(kRequest, "task.sample", fmt::format("{} POIs; sample 1 to {}", count, kMaxTaskPois));
  }
  return scene_files::sample_pois_on_surface(scene.mesh(), count, seed, scene.config().pois.skip_ground);
}

std::vector<TaskCoverage> task_coverage(const Roadmap& roadmap, std::size_t scene_pois,
                                        std::span<const InspectionTask> tasks) {
  const Cover cover(roadmap);
  std::vector<TaskCoverage> out;
  std::size_t first = scene_pois;
  for (const InspectionTask& t : tasks) {
    if (t.removed) {
      first += t.pois.size();
      continue;
    }
    TaskCoverage c{t.name, first, t.pois.size(), 0, 0};
    for (std::size_t id = first; id < first + t.pois.size() && id < roadmap.poi_count(); ++id) {
      c.covered += Cover::has(cover.all, id) ? 1 : 0;
      c.covered_root += Cover::has(cover.root, id) ? 1 : 0;
    }
    out.push_back(std::move(c));
    first += t.pois.size();
  }
  return out;
}

std::size_t live_task(std::span<const InspectionTask> tasks, const std::string& name) {
  bool was_removed = false;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (tasks[i].name == name && !tasks[i].removed) return i;
    was_removed = was_removed || tasks[i].name == name;
  }
  throw params::InputError(kRequest, "task",
                           was_removed
                               ? fmt::format("task '{}' was removed already", shown_name(name))
                               : fmt::format("the roadmap has no task '{}' (ispars task list)", shown_name(name)));
}

std::vector<PoiId> task_targets(const Roadmap& roadmap, std::size_t scene_pois, std::span<const InspectionTask> tasks,
                                const std::string& name) {
  const std::size_t index = live_task(tasks, name);
  const std::size_t first = first_ids(scene_pois, tasks)[index];
  const std::size_t end = std::min(first + tasks[index].pois.size(), roadmap.poi_count());
  const Cover cover(roadmap);
  std::vector<PoiId> targets;
  for (std::size_t id = first; id < end; ++id) {
    if (Cover::has(cover.root, id)) targets.push_back(static_cast<PoiId>(id));
  }
  if (targets.empty()) {
    throw params::InputError(kRequest, "task",
                             fmt::format("no POI of task '{}' is seen from the root's component of the roadmap", name));
  }
  return targets;
}

std::vector<PoiId> live_targets(const Roadmap& roadmap, std::size_t scene_pois, std::span<const InspectionTask> tasks) {
  if (std::none_of(tasks.begin(), tasks.end(), [](const InspectionTask& t) { return t.removed; })) return {};
  std::vector<bool> out(roadmap.poi_count(), false);
  const std::vector<std::size_t> first = first_ids(scene_pois, tasks);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    if (!tasks[i].removed) continue;
    for (std::size_t id = first[i]; id < first[i] + tasks[i].pois.size() && id < out.size(); ++id) out[id] = true;
  }
  const Cover cover(roadmap);
  std::vector<PoiId> targets;
  for (std::size_t id = 0; id < out.size(); ++id) {
    if (!out[id] && Cover::has(cover.root, id)) targets.push_back(static_cast<PoiId>(id));
  }
  if (targets.empty()) {
    throw params::InputError(kRequest, "targets",
                             "no POI but removed tasks' is seen from the root's component of the roadmap");
  }
  return targets;
}

std::vector<Vec3> task_pois(std::span<const InspectionTask> tasks) {
  std::vector<Vec3> all;
  for (const InspectionTask& t : tasks) all.insert(all.end(), t.pois.begin(), t.pois.end());
  return all;
}

}  // namespace ispars::service
