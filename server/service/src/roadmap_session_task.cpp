// Inspection tasks on a session's roadmap: the request (checked and queued like an extend), the
// job that adds the task's POIs (RoadmapBuilder::add_pois, then one commit holding the task and
// its guards), a task's removal (one commit, made at once).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

#include "ispars/builders/poi_visibility.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "request_input.hpp"

namespace ispars {

std::size_t RoadmapSession::request_task(InspectionTask task) {
  std::size_t after = 0;
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!damage_.empty()) throw InputError(kRequest, "scene", fmt::format("scene '{}': {}", name_, damage_));
    if (!recipe_) {
      throw InputError(kRequest, "scene",
                       fmt::format("scene '{}' has no roadmap: build one, then add tasks to it", name_));
    }
    if (!takes_pois(recipe_->method)) {
      throw InputError(kRequest, "scene",
                       fmt::format("scene '{}' has a {} roadmap, which cannot take a task without a rebuild (spars, "
                                   "ispars and ispars2 can): add the POIs to the scene file and build again",
                                   name_, to_string(recipe_->method)));
    }
    check_task(*scene_with_tasks_, tasks_, task);
    if (callbacks_.admit_cost) {
      callbacks_.admit_cost(estimate(scene_with_tasks_->with_more_pois(task.pois), *recipe_, samples_done_));
    }
    pending_recipe_.reset();
    pending_samples_ = 0;
    pending_task_ = std::move(task);
    last_error_.clear();
    state_ = SessionState::queued;
    after = live_tasks() + 1;
  }
  notify_status();
  return after;
}

void RoadmapSession::add_task(Job& job, const std::atomic<bool>& stopping) {
  const InspectionTask& task = *job.task;
  const auto t0 = std::chrono::steady_clock::now();
  std::shared_ptr<const Scene> with_tasks;
  std::size_t task_count = 0;
  {
    std::lock_guard lock(mutex_);
    with_tasks = scene_with_tasks_;
    task_count = task_events(tasks_) + 1;
  }
  auto widened = std::make_unique<Scene>(build_scene_->with_more_pois(task.pois));
  auto next = std::make_shared<const Scene>(with_tasks->with_more_pois(task.pois));
  const std::size_t guards = builder_->add_pois(*widened, [&] { return !stopping && !cancel_; });
  build_scene_ = std::move(widened);  // the builder plans in it from now on
  const RoadmapsView view = live_view();
  BuildCommit commit = commit_since(view, job.roadmap_version, job.dense_version);
  commit.tasks = {task};
  commit.task_count = task_count;
  store_->commit(commit);  // durable: from here on the task is the roadmap's
  job.roadmap_version = view.roadmap->version();
  job.dense_version = view.dense ? view.dense->version() : 0;
  auto copy =
      make_published(std::make_shared<const Roadmap>(*view.roadmap), job.recipe.generation, builder_->samples());
  {
    std::lock_guard lock(mutex_);
    tasks_.push_back(task);
    scene_with_tasks_ = std::move(next);
    published_ = std::move(copy);
    dense_vertices_ = view.dense ? view.dense->vertex_count() : 0;
    dense_edges_ = view.dense ? view.dense->edge_count() : 0;
  }
  if (callbacks_.on_commit) {
    callbacks_.on_commit(commit.roadmap, job.recipe.generation, commit.samples, view.roadmap->poi_count());
  }
  spdlog::info("scene '{}': task '{}' added ({} POIs, {} guards) in {:.3f} s", name_, task.name, task.pois.size(),
               guards, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

std::size_t RoadmapSession::remove_task(const std::string& name) {
  // The store has one writer: a job holds job_mutex_ alone from its start to its end (and for a
  // moment after its status turns idle). Shared with verifies, which only read; two removals are
  // kept apart by removal_mutex_. The commit waits on the disk outside mutex_, which every status
  // read takes: what it reads under mutex_ cannot change meanwhile (no job runs, and removals are
  // one at a time).
  const auto job_lock = lock_idle_job<std::shared_lock<std::shared_mutex>>("remove the task");
  std::lock_guard removal(removal_mutex_);
  BuildCommit commit;
  std::size_t index = 0;
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!damage_.empty()) throw InputError(kRequest, "scene", fmt::format("scene '{}': {}", name_, damage_));
    if (!recipe_) throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap, and so no task", name_));
    index = live_task(tasks_, name);
    if (!store_) {
      throw InputError(kRequest, "scene",
                       fmt::format("scene '{}': its store is not open for writing since an earlier failure; extend "
                                   "the roadmap (which reopens it), then remove the task",
                                   name_));
    }
    // A commit that changes no vertex or edge: the roadmaps' versions stay; it marks the task.
    commit.samples = samples_done_;
    commit.roadmap.from_version = commit.roadmap.to_version = published_.roadmap->version();
    commit.dense.from_version = commit.dense.to_version = dense_vertices_ + dense_edges_;
    commit.removed_tasks = {index};
    commit.task_count = task_events(tasks_) + 1;
  }
  store_->commit(commit);  // durable before the reply: a removal acknowledged is never lost
  std::size_t after = 0;
  {
    std::lock_guard lock(mutex_);
    tasks_[index].removed = true;
    last_error_.clear();
    after = live_tasks();
  }
  notify_status();
  spdlog::info("scene '{}': task '{}' removed", name_, name);
  return after;
}

void RoadmapSession::adopt_tasks(std::vector<InspectionTask> tasks) {
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (recipe_ || !tasks_.empty()) {
      throw InputError(kRequest, "scene", fmt::format("scene '{}' has a roadmap or tasks: it adopts none", name_));
    }
  }
  // Checked against the scene's own mesh (a task's POIs lie on it): no lock is held meanwhile,
  // and the takeover that calls this is the only writer of an empty scene.
  std::vector<InspectionTask> checked;
  for (InspectionTask& t : tasks) {
    const bool removed = t.removed;
    t.removed = false;
    check_task(scene_, checked, t);
    t.removed = removed;
    checked.push_back(std::move(t));
  }
  auto with_tasks = std::make_shared<const Scene>(scene_.with_more_pois(task_pois(checked)));
  {
    std::lock_guard lock(mutex_);
    tasks_ = std::move(checked);
    scene_with_tasks_ = std::move(with_tasks);
  }
  notify_status();
}

std::size_t RoadmapSession::live_tasks() const {
  const auto live = std::count_if(tasks_.begin(), tasks_.end(), [](const InspectionTask& t) { return !t.removed; });
  return static_cast<std::size_t>(live);
}

}  // namespace ispars
