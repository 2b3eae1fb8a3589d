// The record's changes made by a running job, by a task's adoption or removal, and by a drop.

#include <fmt/format.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/session_record.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars::service {

void SessionRecord::check_adoptable() const {
  std::lock_guard lock(mutex_);
  check_can_start("scene");
  if (recipe_ || !tasks_.empty()) {
    throw params::InputError(kRequest, "scene",
                             fmt::format("scene '{}' has a roadmap or tasks: it adopts none", name_));
  }
}

void SessionRecord::adopt_tasks(std::vector<InspectionTask> tasks,
                                std::shared_ptr<const planning::Scene> scene_with_tasks) {
  {
    std::lock_guard lock(mutex_);
    tasks_ = std::move(tasks);
    scene_with_tasks_ = std::move(scene_with_tasks);
  }
  notify();
}

std::pair<std::size_t, std::uint64_t> SessionRecord::check_removal(const std::string& name, bool store_open) const {
  std::lock_guard lock(mutex_);
  check_can_change();
  if (!recipe_)
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap, and so no task", name_));
  const std::size_t index = live_task(tasks_, name);
  if (!store_open) {
    throw params::InputError(
        kRequest, "scene",
        fmt::format("scene '{}': its store is not open for writing since an earlier failure; extend "
                    "the roadmap (which reopens it), then remove the task",
                    name_));
  }
  return {index, service::task_events(tasks_) + 1};
}

std::size_t SessionRecord::mark_removed(std::size_t index) {
  std::size_t after = 0;
  {
    std::lock_guard lock(mutex_);
    tasks_[index].removed = true;
    last_error_.clear();
    after = live_tasks();
  }
  notify();
  return after;
}

std::uint64_t SessionRecord::begin_discard() {
  std::lock_guard lock(mutex_);
  check_can_start("scene");
  if (!recipe_ && damage_.empty())
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
  discarding_ = true;  // no request is accepted while the store goes away
  // A new generation: the empty roadmap is newer than the one discarded (replicas resync, and
  // the fleet weighs this daemon's empty scene above older copies elsewhere, also once it is
  // unloaded: the drop mark keeps the generation).
  return std::max(session_detail::new_generation(), published_.generation + 1);
}

void SessionRecord::end_discard() {
  std::lock_guard lock(mutex_);
  discarding_ = false;
}

void SessionRecord::discarded(std::uint64_t empty_generation) {
  {
    std::lock_guard lock(mutex_);
    discarding_ = false;
    damage_.clear();  // an explicit drop discards a damaged store too
    last_error_.clear();
    forget_roadmap(empty_generation);
    state_ = SessionState::empty;
  }
  notify();
}

void SessionRecord::close() {
  std::lock_guard lock(mutex_);
  check_can_start("scene");
  closed_ = true;
}

std::optional<SessionJob> SessionRecord::take(bool stopping, bool& changed) {
  changed = false;
  std::lock_guard lock(mutex_);
  if (state_ != SessionState::queued) return std::nullopt;
  SessionJob job;
  job.build = std::move(pending_recipe_);
  job.samples = pending_samples_;
  job.task = std::move(pending_task_);
  pending_recipe_.reset();
  pending_samples_ = 0;
  pending_task_.reset();
  if (!cancel_ && !stopping) {
    job.recipe = job.build ? *job.build : *recipe_;
    // Taken from the queue: a cancel from now on reaches the job (cancel_), not the queue. While
    // the builder comes back the job is already running.
    state_ = SessionState::building;
    return job;
  }
  // Cancelled while queued: nothing is touched.
  state_ = resting_state();
  samples_target_ = samples_done_;
  last_error_ = cancel_ ? "cancelled before it started" : "daemon stopped before the job started";
  cancel_ = false;
  changed = true;
  return std::nullopt;
}

void SessionRecord::start(const SessionJob& job) {
  std::lock_guard lock(mutex_);
  if (job.build) {
    starting_build_ = job.recipe;
    starting_samples_ = job.samples;
  }
  if (job.task) starting_task_ = job.task;  // likewise a task, until it is committed
}

void SessionRecord::forget_starting(bool stopping) {
  std::lock_guard lock(mutex_);
  if (stopping) return;
  starting_build_.reset();
  starting_task_.reset();
}

void SessionRecord::begin(SessionState state, std::optional<std::uint64_t> target) {
  {
    std::lock_guard lock(mutex_);
    // A new roadmap's target shows from its first commit on, with its recipe: until then the
    // status describes the old roadmap only (a takeover rebuilds from the status).
    if (target) samples_target_ = *target;
    state_ = state;
  }
  notify();
}

void SessionRecord::record_chunk(ChunkRecord chunk) {
  std::lock_guard lock(mutex_);
  if (chunk.new_recipe) {  // the new roadmap is stored: it replaces the old one everywhere now
    recipe_ = std::move(chunk.new_recipe);
    samples_target_ = chunk.target;
    damage_.clear();  // a damaged store, if there was one, was discarded by this build (replace)
  }
  samples_done_ = chunk.samples;
  if (chunk.copy) published_ = std::move(*chunk.copy);
  dense_ = chunk.dense;
}

void SessionRecord::record_task(InspectionTask task, std::shared_ptr<const planning::Scene> scene_with_tasks,
                                PublishedRoadmap copy, DenseCounts dense) {
  std::lock_guard lock(mutex_);
  tasks_.push_back(std::move(task));
  scene_with_tasks_ = std::move(scene_with_tasks);
  published_ = std::move(copy);
  dense_ = dense;
}

void SessionRecord::publish(PublishedRoadmap copy) {
  std::lock_guard lock(mutex_);
  published_ = std::move(copy);
}

bool SessionRecord::publishes(std::uint64_t generation, std::uint64_t samples, std::uint64_t version) const {
  std::lock_guard lock(mutex_);
  return published_.roadmap && published_.generation == generation && published_.samples == samples &&
         published_.roadmap->version() == version;
}

void SessionRecord::end_job(bool stopping) {
  std::lock_guard lock(mutex_);
  if (cancel_) last_error_ = fmt::format("cancelled at {} of {} samples", samples_done_, samples_target_);
  if (stopping && samples_done_ < samples_target_) {
    last_error_ = fmt::format("daemon stopped at {} of {} samples", samples_done_, samples_target_);
  }
  // A stopping daemon's job stays accepted (recorded, resumed at its restart): its target stays
  // in the last status and announcement, so the daemon that takes the scene over reaches it.
  if (!stopping) samples_target_ = samples_done_;
  state_ = SessionState::idle;
  cancel_ = false;
}

void SessionRecord::interrupt_replay(std::string why) {
  std::lock_guard lock(mutex_);
  last_error_ = std::move(why);
  samples_target_ = samples_done_;
  state_ = SessionState::idle;
  cancel_ = false;
}

void SessionRecord::fail(std::string why) {
  std::lock_guard lock(mutex_);
  last_error_ = std::move(why);
  state_ = SessionState::failed;
}

void SessionRecord::settle_failure(const std::string& why) {
  std::lock_guard lock(mutex_);
  if (state_ == SessionState::failed && last_error_ == why) state_ = resting_state();
  cancel_ = false;
}

}  // namespace ispars::service
