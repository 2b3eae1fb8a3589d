#pragma once
// Builds, extends and task additions a daemon accepted and has not finished, kept on disk (DATA_DIR/.jobs/SCENE.json)
// so that a restart resumes them: one running when the daemon stopped or was killed, and one that
// was still queued. A job that ends (its target reached, cancelled, failed) is forgotten.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ispars/roadmap/file_system.hpp"
#include "ispars/service/roadmap_session.hpp"

namespace ispars::service {

/// One accepted job of one scene.
struct PendingJob {
  std::string scene;
  std::uint64_t id = 0;               ///< Tells this job from a later one of the same scene.
  std::optional<BuildRequest> build;  ///< A build (its request as accepted); empty: an extend or a task.
  std::uint64_t generation = 0;       ///< A build: the generation of the roadmap it makes.
  std::uint64_t target = 0;           ///< Samples the roadmap reaches when the job is done.
  /// Times it was resumed after the daemon died under it (a job that kills the daemon stops being
  /// resumed); a clean stop does not count.
  std::uint32_t attempts = 0;
  std::optional<InspectionTask> task;  ///< A task to add (then no build, and target is 0).
  /// The daemon stopped cleanly (SIGTERM, a rolling upgrade) while the job ran or waited: its next
  /// resume is not counted.
  bool stopped_cleanly = false;
};

/// Writes `job` atomically and durably, replacing the scene's earlier record. Throws on a write
/// failure. Not safe for one scene from two threads at once (the caller serialises).
void save_pending_job(const std::filesystem::path& data_dir, const PendingJob& job, FileSystem& fs = disk());

/// Removes the scene's record if it is job `id`'s (0: whichever it is).
void forget_pending_job(const std::filesystem::path& data_dir, const std::string& scene, std::uint64_t id = 0,
                        FileSystem& fs = disk());

/// Marks every record in `data_dir` stopped cleanly (a clean stop, once no worker runs).
void mark_pending_jobs_stopped_cleanly(const std::filesystem::path& data_dir, FileSystem& fs = disk());

/// Every record in `data_dir`. A record that cannot be read is logged and left as it is; the
/// temporary file of a write a crash interrupted is removed.
[[nodiscard]] std::vector<PendingJob> pending_jobs(const std::filesystem::path& data_dir, FileSystem& fs = disk());

}  // namespace ispars::service
