#pragma once
// The writing side of a scene's session: the roadmap builder, the scene it plans in, the store it
// commits to, and the job that runs them. A job is taken from the SessionRecord, resumes the
// builder from the stored roadmaps when it has none (IRIS-C: replaying its recipe), then grows
// the roadmap chunk by chunk (or adds a task's POIs), each chunk committed to the store
// (durable), then recorded and published, then announced. A failure reopens the store and makes
// the record agree with what it holds.
//
// Not thread-safe: its owner calls it with the session's job lock held (alone to run a job or to
// release the store, shared to read the roadmaps).

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/service/build_request.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/session_record.hpp"

namespace ispars::service {

/// Called with each committed batch of the roadmap (on the job's thread, in order), its
/// generation, the samples after it and the roadmap's POI count after it (a task widens it).
using CommitCallback = std::function<void(const RoadmapBatch& batch, std::uint64_t generation, std::uint64_t samples,
                                          std::size_t poi_count)>;

/// Where a session's jobs work: its scene as loaded, its store directory on a file system, its
/// limits. The referenced objects outlive the job.
struct JobSite {
  const std::string& name;
  const planning::Scene& scene;
  const std::filesystem::path& store_dir;
  const SessionLimits& limits;
  FileSystem& fs;
};

/// A session's builder and store, and the jobs that grow its roadmap (see the file comment).
class BuildJob {
 public:
  BuildJob(JobSite site, SessionRecord& record, CommitCallback on_commit);

  /// Takes over the store opened at load and what a builder resumes from.
  void adopt(std::unique_ptr<RoadmapStore> store, std::optional<planning::BuiltRoadmaps> resume_from);
  /// Runs the record's queued job to its end. Returns early, after committing the current
  /// chunk, when `stopping` becomes true or the job is cancelled; a failure is recorded.
  void run(const std::atomic<bool>& stopping);

  /// The store open for writing; nullptr when none is.
  [[nodiscard]] RoadmapStore* store() { return store_.get(); }
  /// Hands the store over (a drop), leaving none open.
  [[nodiscard]] std::unique_ptr<RoadmapStore> release_store() { return std::move(store_); }
  /// Takes back a store released for a drop that failed.
  void restore_store(std::unique_ptr<RoadmapStore> store) { store_ = std::move(store); }
  /// Lets go of the builder, its scene and the recovered roadmaps.
  void clear();
  /// The roadmaps the builder holds, else those recovered; none when the published copy is all.
  [[nodiscard]] std::optional<RoadmapsView> roadmaps() const;

 private:
  struct Run {
    SessionJob job;
    std::uint64_t roadmap_version = 0;  // the last commit's versions
    std::uint64_t dense_version = 0;
  };
  void perform(Run& run, const std::atomic<bool>& stopping);  // a task's addition, or the growth
  void prepare(Run& run, const std::atomic<bool>& stopping);
  void ensure_builder(const std::atomic<bool>& stopping);
  [[nodiscard]] planning::BuiltRoadmaps resumable_roadmaps(const RoadmapRecipe& recipe);
  void replay(const RoadmapRecipe& recipe, const std::atomic<bool>& stopping);
  void grow(Run& run, std::uint64_t target, const std::atomic<bool>& stopping);
  void add_task(Run& run, const std::atomic<bool>& stopping);
  void end(const Run& run, bool stopping);
  // A task's addition stopped (`builder_changed`: part of it reached the builder): why, as logged.
  void task_stopped(const std::string& why, bool builder_changed, bool stopping);
  void fail(std::string error);
  [[nodiscard]] RoadmapsView live_view() const;
  [[nodiscard]] DenseCounts dense_counts() const;
  void announce(const BuildCommit& commit, std::uint64_t generation) const;

  const JobSite site_;
  SessionRecord& record_;
  const CommitCallback on_commit_;
  std::unique_ptr<planning::Scene> build_scene_;
  std::unique_ptr<planning::RoadmapBuilder> builder_;
  std::unique_ptr<RoadmapStore> store_;
  std::optional<planning::BuiltRoadmaps> recovered_;  // the stored roadmaps until a builder resumes from them
};

}  // namespace ispars::service
