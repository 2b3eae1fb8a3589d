// The service's build jobs: each accepted build or extend is recorded before it is queued, runs
// on a build worker, and is forgotten when it ends, unless the daemon is stopping: then the record
// stays, and the next start resumes it.

#include <spdlog/spdlog.h>

#include "ispars/input_error.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "ispars/service/roadmap_service.hpp"

namespace ispars {
namespace {

constexpr const char* kRequest = "request";

}  // namespace

void RoadmapService::build(const std::string& scene, const BuildRequest& request) {
  const auto s = session(scene);
  PendingJob job{scene, next_job_id_++, request, 0, request.samples};
  job.generation = s->request_build(request);
  try {
    save_pending_job(settings_.data_dir, job);
  } catch (const std::exception& e) {
    (void)s->cancel();  // queued: cancelled at once, nothing touched
    throw InputError(kRequest, "scene", fmt::format("the build of scene '{}' could not be recorded: {}", scene, e.what()));
  }
  schedule(s, job.id);
}

void RoadmapService::extend(const std::string& scene, std::uint64_t samples) {
  const auto s = session(scene);
  PendingJob job{scene, next_job_id_++, std::nullopt, 0, 0};
  job.target = s->request_extend(samples);
  try {
    save_pending_job(settings_.data_dir, job);
  } catch (const std::exception& e) {
    (void)s->cancel();
    throw InputError(kRequest, "scene", fmt::format("the extend of scene '{}' could not be recorded: {}", scene, e.what()));
  }
  schedule(s, job.id);
}

void RoadmapService::schedule(const std::shared_ptr<RoadmapSession>& session, std::uint64_t job_id) {
  builds_.submit([this, session, job_id] {
    spdlog::info("scene '{}': job started", session->name());
    session->run_job(stopping_);
    const SessionStatus st = session->status();
    if (st.state == SessionState::failed) {
      spdlog::error("scene '{}': job failed: {}", session->name(), st.last_error);
    } else {
      spdlog::info("scene '{}': job ended at {} samples, {} vertices, {} edges{}", session->name(), st.samples_done,
                   st.vertices, st.edges, st.last_error.empty() ? "" : " (" + st.last_error + ")");
    }
    // Done, cancelled or failed: forgotten. Stopped by the daemon stopping: resumed at its start.
    if (!stopping_) forget_pending_job(settings_.data_dir, session->name(), job_id);
  });
}

void RoadmapService::resume_pending_jobs() {
  for (const PendingJob& job : pending_jobs(settings_.data_dir)) {
    try {
      auto s = session_or_null(job.scene);
      if (!s && job.build && !std::filesystem::exists(settings_.data_dir / job.scene / "recipe.json")) {
        s = load(job.scene).first;  // a first build that never committed: its scene is loaded for it
      }
      if (!s) {
        throw std::runtime_error("its scene is not loaded here (unloaded, or held by another daemon)");
      }
      const SessionStatus st = s->status();
      const bool committed = !job.build || (st.recipe && st.recipe->generation == job.generation);
      if (!committed) {
        BuildRequest again = *job.build;
        again.replace = again.replace || st.recipe.has_value();
        spdlog::info("scene '{}': resuming a build that had not committed: {} samples, seed {}", job.scene,
                     again.samples, again.seed);
        build(job.scene, again);
      } else if (st.samples_done < job.target) {
        spdlog::info("scene '{}': resuming an interrupted job at {} of {} samples", job.scene, st.samples_done,
                     job.target);
        extend(job.scene, job.target - st.samples_done);
      } else {
        forget_pending_job(settings_.data_dir, job.scene, job.id);
      }
    } catch (const std::exception& e) {
      spdlog::error("scene '{}': the job recorded before the last stop is not resumed: {}", job.scene, e.what());
      forget_pending_job(settings_.data_dir, job.scene, job.id);
    }
  }
}

}  // namespace ispars
