#include "ispars/service/session_record.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars::service {

std::uint64_t session_detail::new_generation() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
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

SessionRecord::SessionRecord(std::string name, const planning::Scene& scene,
                             std::function<void(const SessionStatus&)> on_status)
    : name_(std::move(name)),
      scene_(scene),
      on_status_(std::move(on_status)),
      scene_with_tasks_(std::make_shared<const planning::Scene>(scene)) {
  published_.roadmap = std::make_shared<const Roadmap>(scene.pois().size());
}

SessionStatus SessionRecord::status_locked() const {
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
  s.dense_vertices = dense_.vertices;
  s.dense_edges = dense_.edges;
  s.poi_count = scene_with_tasks_->pois().size();
  s.tasks = live_tasks();
  s.task_events = service::task_events(tasks_) + (accepted_task() ? 1 : 0);
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

SessionStatus SessionRecord::status() const {
  std::lock_guard lock(mutex_);
  return status_locked();
}

void SessionRecord::notify() const {
  if (on_status_) on_status_(status());
}

PublishedRoadmap SessionRecord::published() const {
  std::lock_guard lock(mutex_);
  return published_;
}

SessionRoadmap SessionRecord::served() const {
  std::lock_guard lock(mutex_);
  return {published_, recipe_, scene_with_tasks_, samples_done_, samples_target_, dense_};
}

std::vector<InspectionTask> SessionRecord::tasks() const {
  std::lock_guard lock(mutex_);
  return tasks_;
}

const InspectionTask* SessionRecord::accepted_task() const {
  if (pending_task_ && state_ == SessionState::queued) return &*pending_task_;
  if (!starting_task_) return nullptr;
  const bool committed = std::any_of(tasks_.begin(), tasks_.end(), [&](const InspectionTask& t) {
    return t.name == starting_task_->name && !t.removed;
  });
  return committed ? nullptr : &*starting_task_;
}

std::vector<InspectionTask> SessionRecord::accepted_tasks() const {
  std::lock_guard lock(mutex_);
  std::vector<InspectionTask> out = tasks_;
  if (const InspectionTask* t = accepted_task()) out.push_back(*t);
  return out;
}

std::shared_ptr<const planning::Scene> SessionRecord::scene_with_tasks() const {
  std::lock_guard lock(mutex_);
  return scene_with_tasks_;
}

std::uint64_t SessionRecord::task_events() const {
  std::lock_guard lock(mutex_);
  return service::task_events(tasks_);
}

bool SessionRecord::busy() const {
  std::lock_guard lock(mutex_);
  return state_ == SessionState::queued || state_ == SessionState::building || state_ == SessionState::replaying;
}

std::size_t SessionRecord::live_tasks() const {
  const auto live = std::count_if(tasks_.begin(), tasks_.end(), [](const InspectionTask& t) { return !t.removed; });
  return static_cast<std::size_t>(live);
}

void SessionRecord::take_stored(std::optional<StoredRoadmap> stored, SessionState state, std::string error) {
  std::lock_guard lock(mutex_);
  last_error_ = std::move(error);
  if (stored) {
    recipe_ = std::move(stored->recipe);
    tasks_ = std::move(stored->tasks);
    scene_with_tasks_ = std::move(stored->scene_with_tasks);
    published_ = std::move(stored->published);
    dense_ = stored->dense;
  } else {
    forget_roadmap(0);
  }
  samples_done_ = samples_target_ = published_.samples;
  state_ = state;
  cancel_ = false;
}

void SessionRecord::forget_roadmap(std::uint64_t generation) {
  recipe_.reset();
  tasks_.clear();  // the tasks were the roadmap's: they go with it
  scene_with_tasks_ = std::make_shared<const planning::Scene>(scene_);
  published_ = make_published(std::make_shared<const Roadmap>(scene_.pois().size()), generation, 0);
  dense_ = {};
  samples_done_ = samples_target_ = 0;
}

void SessionRecord::refuse(std::string why) {
  // Loaded, FAILED, and serving nothing from the store, whose files stay as they are until an
  // explicit drop (or build with replace) discards them.
  std::lock_guard lock(mutex_);
  damage_ = std::move(why);
  last_error_ = damage_;
  state_ = SessionState::failed;
}

void SessionRecord::keep_drop_generation(std::uint64_t generation) {
  std::lock_guard lock(mutex_);
  published_.generation = generation;
}

void SessionRecord::check_can_change() const {
  check_can_start("scene");
  if (!damage_.empty()) throw params::InputError(kRequest, "scene", fmt::format("scene '{}': {}", name_, damage_));
}

void SessionRecord::check_can_start(const char* field) const {
  if (closed_) throw params::InputError(kRequest, "scene", fmt::format("scene '{}' was unloaded", name_));
  if (discarding_) throw params::InputError(kRequest, "scene", fmt::format("scene '{}' is being dropped", name_));
  if (state_ == SessionState::queued || state_ == SessionState::building || state_ == SessionState::replaying) {
    throw params::InputError(kRequest, field, fmt::format("a build is already running on scene '{}'", name_));
  }
}

std::uint64_t SessionRecord::accept_build(RoadmapRecipe recipe, const BuildRequest& request,
                                          const std::function<void()>& admit) {
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!damage_.empty() && !request.replace) {
      throw params::InputError(kRequest, "replace",
                               fmt::format("scene '{}': {}; set replace to discard it and build anew", name_, damage_));
    }
    if (recipe_ && !request.replace) {
      throw params::InputError(kRequest, "replace",
                               fmt::format("scene '{}' already has a roadmap ({} samples); set replace to rebuild it",
                                           name_, samples_done_));
    }
    if (admit) admit();  // the last check: nothing refuses after it
    // Increasing, even if the clock steps back, so replicas always see a new roadmap as new, and
    // above a drop's (the published empty roadmap's) too.
    recipe.generation = request.generation != 0
                            ? request.generation
                            : std::max({session_detail::new_generation(), (recipe_ ? recipe_->generation : 0) + 1,
                                        published_.generation + 1});
    pending_recipe_ = recipe;  // the job makes it the roadmap's recipe when it starts
    pending_samples_ = request.samples;
    last_error_.clear();
    state_ = SessionState::queued;
  }
  notify();
  return recipe.generation;
}

std::uint64_t SessionRecord::accept_extend(std::uint64_t samples, const Admit& admit) {
  std::uint64_t target = 0;
  {
    std::lock_guard lock(mutex_);
    check_can_change();
    if (!recipe_)
      throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap to extend", name_));
    if (admit) admit(*scene_with_tasks_, *recipe_, samples_done_ + samples);
    pending_recipe_.reset();
    pending_samples_ = samples;
    last_error_.clear();
    state_ = SessionState::queued;
    target = samples_done_ + samples;
    // Accepted: the target is in the status (and so in the fleet's announcement, which a
    // takeover or a handover continues to) from now on, not from when a worker starts the job.
    samples_target_ = target;
  }
  notify();
  return target;
}

std::size_t SessionRecord::accept_task(InspectionTask task, const Admit& admit) {
  std::size_t after = 0;
  {
    std::lock_guard lock(mutex_);
    check_can_change();
    if (!recipe_) {
      throw params::InputError(kRequest, "scene",
                               fmt::format("scene '{}' has no roadmap: build one, then add tasks to it", name_));
    }
    if (!planning::takes_pois(recipe_->method)) {
      throw params::InputError(
          kRequest, "scene",
          fmt::format("scene '{}' has a {} roadmap, which cannot take a task without a rebuild (spars, "
                      "ispars and ispars2 can): add the POIs to the scene file and build again",
                      name_, to_string(recipe_->method)));
    }
    check_task(*scene_with_tasks_, tasks_, task);
    if (admit) admit(scene_with_tasks_->with_more_pois(task.pois), *recipe_, samples_done_);
    pending_recipe_.reset();
    pending_samples_ = 0;
    pending_task_ = std::move(task);
    last_error_.clear();
    state_ = SessionState::queued;
    after = live_tasks() + 1;
  }
  notify();
  return after;
}

CancelReach SessionRecord::cancel() {
  {
    std::lock_guard lock(mutex_);
    if (state_ == SessionState::building || state_ == SessionState::replaying) {
      cancel_ = true;
      return CancelReach::signalled;
    }
    if (state_ != SessionState::queued) return CancelReach::none;
    // Not started: cancelled now, not when a build worker gets to it (take() then finds it no
    // longer queued).
    pending_recipe_.reset();
    pending_samples_ = 0;
    pending_task_.reset();
    state_ = resting_state();
    samples_target_ = samples_done_;
    last_error_ = "cancelled before it started";
  }
  notify();
  return CancelReach::dequeued;
}

}  // namespace ispars::service
