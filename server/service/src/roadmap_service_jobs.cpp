// The service's build jobs (JobQueue: each recorded as it is accepted, forgotten when it ends), and
// the resume at start of those recorded before the last stop: at most kMaxResumes times after the
// daemon died under a job; resumes after clean stops are not counted.

#include <spdlog/spdlog.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "request_input.hpp"

namespace ispars::service {
namespace {

constexpr std::uint32_t kMaxResumes = 3;  // a job that takes the daemon down with it is given up then

}  // namespace

void RoadmapService::build(const std::string& scene, const BuildRequest& request) {
  accept(scene, request, request.samples, 0);
}

void RoadmapService::extend(const std::string& scene, std::uint64_t samples) {
  accept(scene, std::nullopt, samples, 0);
}

void RoadmapService::accept(const std::string& scene, const std::optional<BuildRequest>& build, std::uint64_t samples,
                            std::uint32_t attempts) {
  jobs_.accept(session(scene), scene, build, samples, attempts);
}

std::size_t RoadmapService::add_task(const std::string& scene, InspectionTask task) {
  return accept_task(scene, std::move(task), 0);
}

std::size_t RoadmapService::remove_task(const std::string& scene, const std::string& name) {
  return session(scene)->remove_task(name);
}

std::size_t RoadmapService::accept_task(const std::string& scene, InspectionTask task, std::uint32_t attempts) {
  return jobs_.accept_task(session(scene), scene, std::move(task), attempts);
}

void RoadmapService::resume_pending_jobs() {
  for (const PendingJob& job : pending_jobs(settings_.data_dir, fs_)) {
    try {
      if (!job.stopped_cleanly && job.attempts >= kMaxResumes) {
        throw std::runtime_error(
            fmt::format("resumed {} times already, and the daemon died under it each time", job.attempts));
      }
      const std::uint32_t attempts = job.stopped_cleanly ? job.attempts : job.attempts + 1;
      auto s = session_or_null(job.scene);
      if (!s && job.build && !fs_.exists(settings_.data_dir / job.scene / "recipe.json")) {
        s = load(job.scene).first;  // a first build that never committed: its scene is loaded for it
      }
      if (!s) throw std::runtime_error("its scene is not loaded here (unloaded, or held by another daemon)");
      if (job.task) {
        const auto tasks = s->tasks();
        const bool added =
            std::any_of(tasks.begin(), tasks.end(), [&](const InspectionTask& t) { return t.name == job.task->name; });
        if (added) {
          jobs_.forget(job.scene, job.id);
        } else {
          spdlog::info("scene '{}': resuming the addition of task '{}'", job.scene, job.task->name);
          (void)accept_task(job.scene, *job.task, attempts);
        }
        continue;
      }
      const SessionStatus st = s->status();
      // A store of the build's lineage with no commit in it (a power cut after its recipe was
      // durable and before its first commit was) is not a roadmap to extend: built again.
      const bool committed =
          !job.build || (st.recipe && st.recipe->generation == job.generation && st.samples_done > 0);
      if (!committed) {
        BuildRequest again = *job.build;
        again.replace = again.replace || st.recipe.has_value();
        spdlog::info("scene '{}': resuming a build that had not committed: {} samples, seed {}", job.scene,
                     again.samples, again.seed);
        accept(job.scene, again, again.samples, attempts);
      } else if (st.samples_done < job.target) {
        spdlog::info("scene '{}': resuming an interrupted job at {} of {} samples", job.scene, st.samples_done,
                     job.target);
        accept(job.scene, std::nullopt, job.target - st.samples_done, attempts);
      } else {
        jobs_.forget(job.scene, job.id);
      }
    } catch (const std::exception& e) {
      spdlog::error("scene '{}': the job recorded before the last stop is not resumed: {}", job.scene, e.what());
      jobs_.forget(job.scene, job.id);
    }
  }
}

}  // namespace ispars::service
