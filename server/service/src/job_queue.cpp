#include "ispars/service/job_queue.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "ispars/params/input_error.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "request_input.hpp"

namespace ispars::service {

JobQueue::JobQueue(unsigned workers, std::filesystem::path data_dir, FileSystem& fs, const std::atomic<bool>& stopping)
    : data_dir_(std::move(data_dir)),
      fs_(fs),
      stopping_(stopping),
      next_id_(static_cast<std::uint64_t>(std::chrono::system_clock::now().time_since_epoch().count())),
      workers_(std::max(1u, workers)) {}

void JobQueue::accept(const std::shared_ptr<RoadmapSession>& session, const std::string& scene,
                      const std::optional<BuildRequest>& build, std::uint64_t samples, std::uint32_t attempts) {
  PendingJob job{scene, next_id_++, build, 0, 0, attempts, std::nullopt};
  {
    // One step: a cancel's or an ended job's removal of the record comes before or after it.
    std::lock_guard lock(mutex_);
    if (build) {
      job.generation = session->request_build(*build);
      job.target = build->samples;
    } else {
      job.target = session->request_extend(samples);
    }
    record(session, job);
  }
  schedule(session, job.id);
}

std::size_t JobQueue::accept_task(const std::shared_ptr<RoadmapSession>& session, const std::string& scene,
                                  InspectionTask task, std::uint32_t attempts) {
  PendingJob job{scene, next_id_++, std::nullopt, 0, 0, attempts, task};
  std::size_t after = 0;
  {
    std::lock_guard lock(mutex_);
    after = session->request_task(std::move(task));
    record(session, job);
  }
  schedule(session, job.id);
  return after;
}

void JobQueue::record(const std::shared_ptr<RoadmapSession>& session, const PendingJob& job) {
  try {
    save_pending_job(data_dir_, job, fs_);
  } catch (const std::exception& e) {
    (void)session->cancel();  // queued, so cancelled at once: nothing touched
    throw params::InputError(kRequest, "scene",
                             fmt::format("the job on scene '{}' could not be recorded: {}", job.scene, e.what()));
  }
}

void JobQueue::forget(const std::string& scene, std::uint64_t job_id) {
  std::lock_guard lock(mutex_);
  try {
    forget_pending_job(data_dir_, scene, job_id, fs_);
  } catch (const std::exception& e) {  // the record stays: the next start finds its job done
    spdlog::error("scene '{}': the finished job's record could not be removed: {}", scene, e.what());
  }
}

void JobQueue::mark_stopped_cleanly() {
  try {  // the jobs left are resumed at the next start, and this stop does not count against them
    std::lock_guard lock(mutex_);
    mark_pending_jobs_stopped_cleanly(data_dir_, fs_);
  } catch (const std::exception& e) {
    spdlog::error("the pending jobs could not be marked as stopped cleanly ({}): their next resume counts", e.what());
  }
}

void JobQueue::schedule(const std::shared_ptr<RoadmapSession>& session, std::uint64_t job_id) {
  workers_.submit([this, session, job_id] {
    spdlog::info("scene '{}': job started", session->name());
    session->run_job(stopping_);
    const SessionStatus st = session->status();
    if (st.state == SessionState::failed) {
      spdlog::error("scene '{}': job failed: {}", session->name(), st.last_error);
    } else {
      spdlog::info("scene '{}': job ended at {} samples, {} vertices, {} edges{}", session->name(), st.samples_done,
                   st.vertices, st.edges, st.last_error.empty() ? "" : " (" + st.last_error + ")");
    }
    // Done, cancelled or failed: forgotten (unless a later job of the scene has recorded itself
    // meanwhile). Stopped by the daemon stopping: resumed at its start.
    if (!stopping_) forget(session->name(), job_id);
  });
}

}  // namespace ispars::service
