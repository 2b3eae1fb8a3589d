#include "ispars/service/roadmap_session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "ispars/planning/scene/scene_fingerprint.hpp"
#include "ispars/service/session_recovery.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars::service {

planning::Scene session_detail::scene_for(const planning::Scene& scene, const RoadmapRecipe& recipe) {
  return planning::recipe_scene(scene, recipe, kRequest);
}

RoadmapSession::RoadmapSession(std::string name, planning::Scene scene, std::filesystem::path store_dir,
                               SessionLimits limits, SessionCallbacks callbacks, FileSystem& fs)
    : name_(std::move(name)),
      scene_(std::move(scene)),
      store_dir_(std::move(store_dir)),
      limits_(limits),
      callbacks_(std::move(callbacks)),
      fs_(fs),
      fingerprint_(scene_fingerprint(scene_)),  // of the scene file's POIs: a task is not an edit of the scene
      record_(name_, scene_, callbacks_.on_status),
      job_(JobSite{name_, scene_, store_dir_, limits_, fs_}, record_, callbacks_.on_commit) {
  RecoveredSession r = recover_session(name_, scene_, fingerprint_, store_dir_, limits_, fs_);
  if (!r.refused.empty()) {
    record_.refuse(std::move(r.refused));
    return;
  }
  if (!r.stored) {
    // Dropped here before: the empty roadmap keeps the drop's generation, which the fleet weighs.
    if (r.dropped_generation) record_.keep_drop_generation(*r.dropped_generation);
    return;
  }
  job_.adopt(std::move(r.store), std::move(r.resume_from));
  record_.take_stored(std::move(r.stored), SessionState::idle, "");
  recovery_note_ = std::move(r.note);
  torn_tail_note_ = std::move(r.torn_tail_note);
}

RoadmapSession::~RoadmapSession() = default;

planning::BuildCost RoadmapSession::estimate(const planning::Scene& scene, const RoadmapRecipe& recipe,
                                             std::uint64_t total_samples) const {
  std::call_once(free_fraction_once_, [&] { free_fraction_ = free_fraction(scene_); });
  return planning::estimate_build_cost(scene, recipe, total_samples, free_fraction_);
}

SessionRecord::Admit RoadmapSession::admit() const {
  if (!callbacks_.admit_cost) return {};
  return [this](const planning::Scene& scene, const RoadmapRecipe& recipe, std::uint64_t samples) {
    callbacks_.admit_cost(estimate(scene, recipe, samples));
  };
}

std::uint64_t RoadmapSession::request_build(const BuildRequest& request) {
  RoadmapRecipe recipe = requested_recipe(name_, scene_, request, limits_);
  recipe.scene_fingerprint = fingerprint_;
  recipe.builder_version = kBuilderVersion;
  // Estimated before the record's lock is taken: the first estimate measures the scene's free space.
  const planning::BuildCost cost = estimate(*scene_with_tasks(), recipe, request.samples);
  return record_.accept_build(std::move(recipe), request, [&] {
    if (callbacks_.admit_cost) callbacks_.admit_cost(cost);
  });
}

std::uint64_t RoadmapSession::request_extend(std::uint64_t samples) {
  check_samples(samples, limits_);
  return record_.accept_extend(samples, admit());
}

std::size_t RoadmapSession::request_task(InspectionTask task) { return record_.accept_task(std::move(task), admit()); }

bool RoadmapSession::cancel() {
  readers_->stop_all(fmt::format("cancelled by a cancel request on scene '{}'", name_));
  return record_.cancel() != CancelReach::none;
}

void RoadmapSession::run_job(const std::atomic<bool>& stopping) {
  // A running verify stops (a job is a writer of the roadmaps it reads); new ones are refused
  // while the job is queued or runs (lock_idle_job).
  readers_->stop_all(fmt::format("a build started on scene '{}'", name_));
  std::lock_guard job_lock(job_mutex_);
  job_.run(stopping);
}

bool RoadmapSession::busy() const { return record_.busy(); }

template <typename Lock>
Lock RoadmapSession::lock_idle_job(std::string_view what) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  for (;;) {
    Lock job(job_mutex_, std::try_to_lock);
    const bool queued_or_running = busy();
    if (job.owns_lock() && !queued_or_running) return job;
    if (queued_or_running) {
      throw params::InputError(kRequest, "scene",
                               fmt::format("a build is running on scene '{}'; {} when it is idle", name_, what));
    }
    if (std::chrono::steady_clock::now() >= deadline) {
      throw params::InputError(kRequest, "scene",
                               fmt::format("scene '{}' is busy with a verify or a drop; {} later", name_, what));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

planning::BuildCost RoadmapSession::expected_cost() const {
  const SessionRoadmap served = record_.served();
  if (!served.recipe) return {};
  return estimate(*served.scene_with_tasks, *served.recipe, std::max(served.samples_target, served.samples_done));
}

SessionStatus RoadmapSession::status() const { return record_.status(); }
PublishedRoadmap RoadmapSession::published() const { return record_.published(); }
std::vector<InspectionTask> RoadmapSession::tasks() const { return record_.tasks(); }
std::vector<InspectionTask> RoadmapSession::accepted_tasks() const { return record_.accepted_tasks(); }
std::shared_ptr<const planning::Scene> RoadmapSession::scene_with_tasks() const { return record_.scene_with_tasks(); }

planning::RoadmapPath RoadmapSession::path(const Vec3& from, const Vec3& to) const {
  const SessionRoadmap served = record_.served();
  if (!served.recipe || served.published.roadmap->vertex_count() == 0) {
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap yet", name_));
  }
  return planning::plan_path(scene_, *served.published.roadmap, from, to, served.recipe->sparse_delta);
}

planning::VerificationReport RoadmapSession::verify(std::chrono::milliseconds budget) const {
  std::unique_ptr<ReaderGate::Pass> pass;
  try {
    pass = readers_->enter(std::chrono::steady_clock::now() + budget);
  } catch (const ReaderRefused& e) {
    throw params::InputError(kRequest, "scene", fmt::format("{}; verify later", e.what()));
  }
  const auto job = lock_idle_job<std::shared_lock<std::shared_mutex>>("verify");
  const planning::VerifyKeepGoing keep_going = [&] { return pass->keep_going(); };
  try {
    return verify_locked(keep_going);
  } catch (const planning::VerificationStopped&) {
    const std::string why = pass->keep_going() ? std::string() : pass->why_stopped();
    throw params::InputError(
        kRequest, "scene",
        fmt::format(
            "the verify of scene '{}' was stopped: {}", name_,
            why == "its time ran out" ? fmt::format("its budget of {:.1f} s ran out", budget.count() / 1000.0) : why));
  }
}

void RoadmapSession::stop_readers(const std::string& why) { readers_->stop_all(why); }

planning::VerificationReport RoadmapSession::verify_locked(const planning::VerifyKeepGoing& keep_going) const {
  // No job runs (the job lock is held): the record's samples are the roadmap's.
  const SessionRoadmap served = record_.served();
  if (!served.recipe) throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
  const RoadmapRecipe& recipe = *served.recipe;
  const planning::Scene scene = session_detail::scene_for(*served.scene_with_tasks, recipe);
  const auto check = [&](const Roadmap& roadmap, const Roadmap* dense, std::span<const VertexId> dense_ids) {
    return planning::verify_recipe_roadmaps(scene, recipe, served.samples_done, roadmap, dense, dense_ids, keep_going);
  };
  if (const std::optional<RoadmapsView> held = job_.roadmaps())
    return check(*held->roadmap, held->dense, held->dense_ids);
  // No builder and nothing recovered: a method that resumes from its roadmap, idle, whose
  // published roadmap is the stored one.
  if (!planning::resumes_from_roadmap(recipe.method) || served.published.generation != recipe.generation) {
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
  }
  return check(*served.published.roadmap, nullptr, {});
}

// verify() takes the job lock shared; the writers (roadmap_session_writers.cpp) take it alone.
template std::shared_lock<std::shared_mutex> RoadmapSession::lock_idle_job<std::shared_lock<std::shared_mutex>>(
    std::string_view) const;
template std::unique_lock<std::shared_mutex> RoadmapSession::lock_idle_job<std::unique_lock<std::shared_mutex>>(
    std::string_view) const;

}  // namespace ispars::service
