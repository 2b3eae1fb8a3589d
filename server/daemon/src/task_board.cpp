#include "ispars/server/task_board.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "ispars/service/roadmap_store.hpp"

namespace ispars::server {

void TaskBoard::seen(const msg::SceneTask& t) {
  const std::string scene = t.scene().to_string();
  const bool finite = std::all_of(t.pois().begin(), t.pois().end(), [](const msg::Point& p) {
    return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
  });
  if (t.index() >= service::kMaxTasks || t.pois().size() > service::kMaxTaskPois || t.pois().empty() ||
      !service::valid_task_name(t.name().to_string()) || !finite || scene.size() > 64) {
    spdlog::warn("ignored task {} of scene '{}' from daemon {}: out of bounds", t.index(), scene.substr(0, 64),
                 t.server_id().to_string().substr(0, 64));
    return;
  }
  Entry e;
  e.generation = t.generation();
  e.task.name = t.name().to_string();
  e.task.removed = t.removed();
  e.task.pois.reserve(t.pois().size());
  for (const msg::Point& p : t.pois()) e.task.pois.emplace_back(p.x(), p.y(), p.z());
  std::lock_guard lock(mutex_);
  tasks_[{scene, t.server_id().to_string(), t.index()}] = std::move(e);
}

std::size_t TaskBoard::size() const {
  std::lock_guard lock(mutex_);
  return tasks_.size();
}

std::optional<std::vector<service::InspectionTask>> TaskBoard::tasks_of(const std::string& scene,
                                                                        const std::string& server,
                                                                        std::uint64_t generation, std::uint64_t events,
                                                                        std::optional<std::size_t> task_pois) const {
  std::vector<service::InspectionTask> out;
  std::lock_guard lock(mutex_);
  for (auto it = tasks_.lower_bound({scene, server, 0});
       it != tasks_.end() && std::get<0>(it->first) == scene && std::get<1>(it->first) == server; ++it) {
    // Up to the events asked for: an index past them is a task addition later cancelled.
    if (task_events(out) >= events) break;
    if (std::get<2>(it->first) != out.size() || it->second.generation != generation) break;
    out.push_back(it->second.task);
  }
  std::size_t pois = 0;
  for (const service::InspectionTask& t : out) pois += t.pois.size();
  if (task_events(out) != events || (task_pois && pois != *task_pois)) return std::nullopt;
  return out;
}

}  // namespace ispars::server
