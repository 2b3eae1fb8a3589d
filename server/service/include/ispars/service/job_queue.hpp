#pragma once
// The service's build jobs: each accepted build, extend or task addition is recorded in the data
// directory as it is accepted (pending_jobs.hpp), runs on a build worker, and is forgotten when it
// ends, unless the service is stopping: then its record stays, and the next start resumes it.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "ispars/roadmap/build_request.hpp"
#include "ispars/roadmap/file_system.hpp"
#include "ispars/service/inspection_task.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::service {

struct PendingJob;  // pending_jobs.hpp

/// Accepts, records, runs and forgets build jobs; safe from many threads.
class JobQueue {
 public:
  /// `workers` jobs run at once; records go in `data_dir` on `fs`; `stopping` is the service's stop.
  JobQueue(unsigned workers, std::filesystem::path data_dir, FileSystem& fs, const std::atomic<bool>& stopping);

  /// Asks `session` (scene `scene`) for a build (`build`) or an extend by `samples`, records the
  /// job in the same step, and queues it. `attempts`: resumes after the daemon died under it.
  /// Throws InputError when the session refuses it or the record cannot be written.
  void accept(const std::shared_ptr<RoadmapSession>& session, const std::string& scene,
              const std::optional<BuildRequest>& build, std::uint64_t samples, std::uint32_t attempts);
  /// The same for the addition of `task`; returns the scene's task count after it.
  std::size_t accept_task(const std::shared_ptr<RoadmapSession>& session, const std::string& scene, InspectionTask task,
                          std::uint32_t attempts);
  /// Removes the record of `scene`'s job `job_id` (0: whichever); a failure is logged.
  void forget(const std::string& scene, std::uint64_t job_id);
  /// Stops the workers: running jobs commit their current chunk and return, queued ones are dropped.
  void stop_workers() { workers_.stop(); }
  /// Marks the records left as stopped cleanly: their resume at the next start does not count.
  void mark_stopped_cleanly();

 private:
  void record(const std::shared_ptr<RoadmapSession>& session, const PendingJob& job);  // mutex_ held
  void schedule(const std::shared_ptr<RoadmapSession>& session, std::uint64_t job_id);

  const std::filesystem::path data_dir_;
  FileSystem& fs_;
  const std::atomic<bool>& stopping_;
  std::atomic<std::uint64_t> next_id_;  // from the clock at start: unlike a previous run's ids
  std::mutex mutex_;                    // a job's acceptance and its record; every read-compare-remove of one
  WorkerPool workers_;
};

}  // namespace ispars::service
