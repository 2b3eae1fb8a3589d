#include "ispars/service/roadmap_session.hpp"

#include "ispars/scene/scene_fingerprint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "ispars/builders/recipe_builder.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/service/session_recovery.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars {
std::uint64_t session_detail::new_generation() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

Scene session_detail::scene_for(const Scene& scene, const RoadmapRecipe& recipe) {
  return recipe_scene(scene, recipe, kRequest);
}

std::string_view to_string(SessionState state) {
  switch (state) {
    case SessionState::empty:
      return "empty";
    case SessionState::idle:
      return "idle";
    case SessionState::queued:
      return "queued";
    case SessionState::replaying:
      return "replaying";
    case SessionState::building:
      return "building";
    case SessionState::failed:
      return "failed";
  }
  return "unknown";
}

RoadmapSession::RoadmapSession(std::string name, Scene scene, std::filesystem::path store_dir, SessionLimits limits,
                               SessionCallbacks callbacks, FileSystem& fs)
    : name_(std::move(name)),
      scene_(std::move(scene)),
      store_dir_(std::move(store_dir)),
      limits_(limits),
      callbacks_(std::move(callbacks)),
      fs_(fs) {
  published_.roadmap = std::make_shared<const Roadmap>(scene_.pois().size());
  scene_with_tasks_ = std::make_shared<const Scene>(scene_);
  fingerprint_ = scene_fingerprint(scene_);  // of the scene file's POIs: a task is not an edit of the scene
  RecoveredSession r = recover_session(name_, scene_, fingerprint_, store_dir_, limits_, fs_);
  if (!r.refused.empty()) {
    refuse_store(std::move(r.refused));
    return;
  }
  if (!r.recipe) {
    // Dropped here before: the empty roadmap keeps the drop's generation, which the fleet weighs.
    if (r.dropped_generation) published_.generation = *r.dropped_generation;
    return;
  }
  store_ = std::move(r.store);
  scene_with_tasks_ = std::move(r.scene_with_tasks);
  tasks_ = std::move(r.tasks);
  recipe_ = std::move(r.recipe);
  samples_done_ = samples_target_ = r.published.samples;
  published_ = std::move(r.published);
  dense_vertices_ = r.dense_vertices;
  dense_edges_ = r.dense_edges;
  recovery_note_ = std::move(r.note);
  torn_tail_note_ = std::move(r.torn_tail_note);
  recovered_ = std::move(r.resume_from);
  state_ = SessionState::idle;
}

RoadmapSession::~RoadmapSession() = default;

void RoadmapSession::refuse_store(std::string why) {
  // Loaded, FAILED, and serving nothing from the store, whose files stay as they are until an
  // explicit drop (or build with replace) discards them.
  store_.reset();
  damage_ = std::move(why);
  last_error_ = damage_;
  state_ = SessionState::failed;
}

void RoadmapSession::check_can_start(const char* field) const {
  if (closed_) throw InputError(kRequest, "scene", fmt::format("scene '{}' was unloaded", name_));
  if (discarding_) throw InputError(kRequest, "scene", fmt::format("scene '{}' is being dropped", name_));
  if (state_ == SessionState::queued || state_ == SessionState::building || state_ == SessionState::replaying) {
    throw InputError(kRequest, field, fmt::format("a build is already running on scene '{}'", name_));
  }
}

std::uint64_t RoadmapSession::request_build(const BuildRequest& request) {
  RoadmapRecipe recipe = requested_recipe(name_, scene_, request, limits_);
  const BuildCost cost = estimate(*scene_with_tasks(), recipe, request.samples);
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!damage_.empty() && !request.replace) {
      throw InputError(kRequest, "replace",
                       fmt::format("scene '{}': {}; set replace to discard it and build anew", name_, damage_));
    }
    if (recipe_ && !request.replace) {
      throw InputError(kRequest, "replace",
                       fmt::format("scene '{}' already has a roadmap ({} samples); set replace to rebuild it", name_,
                                   samples_done_));
    }
    if (callbacks_.admit_cost) callbacks_.admit_cost(cost);  // the last check: nothing refuses after it
    // Increasing, even if the clock steps back, so replicas always see a new roadmap as new, and
    // above a drop's (the published empty roadmap's) too.
    recipe.generation = request.generation != 0
                            ? request.generation
                            : std::max({session_detail::new_generation(), (recipe_ ? recipe_->generation : 0) + 1,
                                        published_.generation + 1});
    recipe.scene_fingerprint = fingerprint_;
    recipe.builder_version = kBuilderVersion;
    pending_recipe_ = recipe;  // the job makes it the roadmap's recipe when it starts
    pending_samples_ = request.samples;
    last_error_.clear();
    state_ = SessionState::queued;
  }
  notify_status();
  return recipe.generation;
}

std::uint64_t RoadmapSession::request_extend(std::uint64_t samples) {
  std::uint64_t target = 0;
  check_samples(samples, limits_);
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!damage_.empty()) throw InputError(kRequest, "scene", fmt::format("scene '{}': {}", name_, damage_));
    if (!recipe_) throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap to extend", name_));
    if (callbacks_.admit_cost) callbacks_.admit_cost(estimate(*scene_with_tasks_, *recipe_, samples_done_ + samples));
    pending_recipe_.reset();
    pending_samples_ = samples;
    last_error_.clear();
    state_ = SessionState::queued;
    target = samples_done_ + samples;
    // Accepted: the target is in the status (and so in the fleet's announcement, which a
    // takeover or a handover continues to) from now on, not from when a worker starts the job.
    samples_target_ = target;
  }
  notify_status();
  return target;
}

bool RoadmapSession::cancel() {
  readers_->stop_all(fmt::format("cancelled by a cancel request on scene '{}'", name_));
  {
    std::lock_guard lock(mutex_);
    if (state_ != SessionState::building && state_ != SessionState::replaying) {
      if (state_ != SessionState::queued) return false;
      // Not started: cancelled now, not when a build worker gets to it (run_job then finds it
      // no longer queued and returns).
      pending_recipe_.reset();
      pending_samples_ = 0;
      pending_task_.reset();
      state_ = recipe_ ? SessionState::idle : SessionState::empty;
      samples_target_ = samples_done_;
      last_error_ = "cancelled before it started";
    } else {
      cancel_ = true;
      return true;
    }
  }
  notify_status();
  return true;
}

bool RoadmapSession::busy() const {
  std::lock_guard lock(mutex_);
  return state_ == SessionState::queued || state_ == SessionState::building || state_ == SessionState::replaying;
}

template <typename Lock>
Lock RoadmapSession::lock_idle_job(std::string_view what) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  for (;;) {
    Lock job(job_mutex_, std::try_to_lock);
    const bool queued_or_running = busy();
    if (job.owns_lock() && !queued_or_running) return job;
    if (queued_or_running) {
      throw InputError(kRequest, "scene",
                       fmt::format("a build is running on scene '{}'; {} when it is idle", name_, what));
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      throw InputError(kRequest, "scene",
                       fmt::format("scene '{}' is busy with a verify or a drop; {} later", name_, what));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

BuildCost RoadmapSession::estimate(const Scene& scene, const RoadmapRecipe& recipe, std::uint64_t total_samples) const {
  std::call_once(free_fraction_once_, [&] { free_fraction_ = free_fraction(scene_); });
  return estimate_build_cost(scene, recipe, total_samples, free_fraction_);
}

BuildCost RoadmapSession::expected_cost() const {
  std::lock_guard lock(mutex_);
  if (!recipe_) return {};
  return estimate(*scene_with_tasks_, *recipe_, std::max(samples_target_, samples_done_));
}

SessionStatus RoadmapSession::status_locked() const {
  SessionStatus s;
  s.scene = name_;
  s.state = state_;
  s.recipe = recipe_;
  s.samples_done = samples_done_;
  s.samples_target = samples_target_;
  s.last_error = last_error_;
  const Roadmap& g = *published_.roadmap;
  s.version = g.version();
  s.vertices = g.vertex_count();
  s.edges = g.edge_count();
  s.components = g.component_count();
  s.dense_vertices = dense_vertices_;
  s.dense_edges = dense_edges_;
  s.poi_count = scene_with_tasks_->pois().size();
  s.tasks = live_tasks();
  s.task_events = task_events(tasks_) + (accepted_task() ? 1 : 0);
  s.pois_covered = published_.pois_covered;
  s.pois_covered_root = published_.pois_covered_root;
  s.generation = published_.generation;
  // An acknowledged build shows as accepted from its acceptance to its first commit: queued,
  // started, or stopped with the daemon (recorded, resumed at the restart).
  if (pending_recipe_ && state_ == SessionState::queued) {
    s.accepted = pending_recipe_;
    s.samples_target = pending_samples_;
  } else if (starting_build_ && (!recipe_ || recipe_->generation != starting_build_->generation)) {
    s.accepted = starting_build_;
    s.samples_target = starting_samples_;
  }
  return s;
}

SessionStatus RoadmapSession::status() const {
  std::lock_guard lock(mutex_);
  return status_locked();
}

void RoadmapSession::notify_status() {
  if (callbacks_.on_status) callbacks_.on_status(status());
}

PublishedRoadmap RoadmapSession::published() const {
  std::lock_guard lock(mutex_);
  return published_;
}

std::vector<InspectionTask> RoadmapSession::tasks() const {
  std::lock_guard lock(mutex_);
  return tasks_;
}

const InspectionTask* RoadmapSession::accepted_task() const {
  if (pending_task_ && state_ == SessionState::queued) return &*pending_task_;
  if (!starting_task_) return nullptr;
  const bool committed = std::any_of(tasks_.begin(), tasks_.end(), [&](const InspectionTask& t) {
    return t.name == starting_task_->name && !t.removed;
  });
  return committed ? nullptr : &*starting_task_;
}

std::vector<InspectionTask> RoadmapSession::accepted_tasks() const {
  std::lock_guard lock(mutex_);
  std::vector<InspectionTask> out = tasks_;
  if (const InspectionTask* t = accepted_task()) out.push_back(*t);
  return out;
}

std::shared_ptr<const Scene> RoadmapSession::scene_with_tasks() const {
  std::lock_guard lock(mutex_);
  return scene_with_tasks_;
}

RoadmapPath RoadmapSession::path(const Vec3& from, const Vec3& to) const {
  PublishedRoadmap p;
  double join_radius = 0.0;
  {
    std::lock_guard lock(mutex_);
    if (!recipe_ || published_.roadmap->vertex_count() == 0) {
      throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap yet", name_));
    }
    p = published_;
    join_radius = recipe_->sparse_delta;
  }
  return plan_path(scene_, *p.roadmap, from, to, join_radius);
}

// verify() (roadmap_session_verify.cpp) takes the job lock shared; the writers of
// roadmap_session_discard.cpp take it alone.
template std::shared_lock<std::shared_mutex> RoadmapSession::lock_idle_job<std::shared_lock<std::shared_mutex>>(
    std::string_view) const;
template std::unique_lock<std::shared_mutex> RoadmapSession::lock_idle_job<std::unique_lock<std::shared_mutex>>(
    std::string_view) const;

}  // namespace ispars
