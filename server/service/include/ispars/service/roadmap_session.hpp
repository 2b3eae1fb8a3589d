#pragma once
// One scene's roadmap as the service holds it: the scene, its persistent roadmap, and the build
// job that grows it. Knows nothing of DDS: the server calls it and forwards its callbacks.
//
// Requests (build, extend, task, cancel, drop) are checked and recorded at once in the session's
// SessionRecord; the job itself runs on a worker thread that calls run_job(), which hands it to
// the BuildJob. Queries read the record's immutable published copies, so they are served from a
// consistent version while the job runs. Each chunk of samples is committed to the store
// (durable), then published to readers, then announced through the callbacks. The store's
// recovery at load is recover_session()'s.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>
#include <string_view>

#include "ispars/planning/builders/build_cost.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/search/path_query.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/service/build_job.hpp"
#include "ispars/service/build_request.hpp"
#include "ispars/service/inspection_task.hpp"
#include "ispars/service/published_roadmap.hpp"
#include "ispars/service/reader_gate.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/session_record.hpp"

namespace ispars::service {

/// A verify running longer than this is stopped and answered with an error naming the budget.
inline constexpr std::chrono::milliseconds kVerifyBudget{300'000};

/// What the session tells its owner.
struct SessionCallbacks {
  /// A committed batch of the roadmap (called on the job's thread, in order), and the roadmap's
  /// POI count after it (a task's commit widens it).
  CommitCallback on_commit;
  /// The status changed (state, progress or counts).
  std::function<void(const SessionStatus& status)> on_status;
  /// Called with the estimate of the roadmap a build or extend would make, as the last check
  /// before it is recorded (with the session's lock held: it must not call into this session).
  /// Throws InputError to refuse it. Not set: no memory budget.
  std::function<void(const planning::BuildCost& cost)> admit_cost;
};

/// One loaded scene: its persistent roadmap, the job that grows it, and consistent reads of it.
class RoadmapSession {
 public:
  /// A session for `scene` named `name`, storing its roadmap in `store_dir` on `fs` (the disk;
  /// tests give a file system of their own). When the directory holds a store, its roadmap is
  /// recovered now (throws std::runtime_error when unreadable).
  RoadmapSession(std::string name, planning::Scene scene, std::filesystem::path store_dir, SessionLimits limits,
                 SessionCallbacks callbacks, FileSystem& fs = disk());
  ~RoadmapSession();
  RoadmapSession(const RoadmapSession&) = delete;
  RoadmapSession& operator=(const RoadmapSession&) = delete;

  /// Records a new build; returns the generation of the roadmap it will make. Throws InputError
  /// (file "request") naming the field when the request is bad, a job is running, or a roadmap
  /// exists and replace is not set.
  std::uint64_t request_build(const BuildRequest& request);
  /// Records an extend by `samples` more samples (same errors; needs a roadmap); returns the
  /// sample count the roadmap will have.
  std::uint64_t request_extend(std::uint64_t samples);
  /// Records the addition of an inspection task to the roadmap (run by run_job, committed as one
  /// step: a crash leaves the roadmap before or after it); returns the scene's task count after
  /// it. Throws InputError (file "request") naming the field when the task is bad (check_task),
  /// a job is queued or running, the scene has no roadmap, or its method cannot take a task
  /// without a rebuild (dense, irisc).
  std::size_t request_task(InspectionTask task);
  /// Removes the task `name`: one commit, durable when this returns. The roadmap is unchanged
  /// (its vertices keep seeing the task's POIs, whose ids stay), but the POIs leave every target
  /// set (tours, coverage) and the name is free again. Returns the tasks left. Throws InputError
  /// (file "request") naming the field: task (none of that name, or removed already), or scene
  /// (no roadmap, a job queued or running, damage, or a store not open for writing). A job that
  /// has just turned idle is waited for (lock_idle_job).
  std::size_t remove_task(const std::string& name);
  /// Asks the running job to stop after its current chunk; false when there is none.
  bool cancel();
  /// Deletes the roadmap and its store (throws InputError while a job runs or without a roadmap).
  void drop();
  /// Keeps the roadmap's store aside (set_aside_store, with `why`) and leaves the scene without a
  /// roadmap, as drop() does; returns where the store went. Same errors as drop().
  std::filesystem::path set_aside(const std::string& why);
  /// Gives a scene with no roadmap the tasks of a roadmap it is about to rebuild (another
  /// daemon's, in a takeover): the build that follows is made with their POIs, and its first
  /// commit records them. Each is checked as a task request is (check_task). Throws InputError
  /// when the scene has a roadmap or a job, or a task fails its check (nothing changed then).
  void adopt_tasks(std::vector<InspectionTask> tasks);
  /// Refuses every later build and extend (the scene is being unloaded) and releases the store,
  /// so that the scene can be loaded again while this session still serves a running tour.
  /// Throws InputError while a job is queued or running.
  void close();

  /// Runs the recorded job to its end on the calling thread. Returns early, after committing the
  /// current chunk, when `stopping` becomes true or the job is cancelled.
  void run_job(const std::atomic<bool>& stopping);

  /// Queries: safe from any thread, consistent, and never wait for the job.
  [[nodiscard]] SessionStatus status() const;
  [[nodiscard]] PublishedRoadmap published() const;
  /// The roadmap's inspection tasks, in order: task k's POIs have the ids after the scene's own
  /// and tasks 0..k-1's.
  [[nodiscard]] std::vector<InspectionTask> tasks() const;
  /// tasks(), then a task addition acknowledged and not committed yet (queued, running, or
  /// stopped with the daemon): what the fleet carries (ispars/tasks; counted in the status's
  /// task_events from the acknowledgement, as an extend's target is in samples_target).
  [[nodiscard]] std::vector<InspectionTask> accepted_tasks() const;
  /// The scene with every task's POIs: what the roadmap is planned and verified in.
  [[nodiscard]] std::shared_ptr<const planning::Scene> scene_with_tasks() const;
  /// A path on the published roadmap (InputError on bad points, see plan_path).
  [[nodiscard]] planning::RoadmapPath path(const Vec3& from, const Vec3& to) const;
  /// Checks the roadmap (validity, costs, Invariant 1 for spars/ispars). Waits for no job: throws
  /// InputError while one runs, or while an unload or a drop holds readers off. Stops (InputError
  /// saying why) within milliseconds when its budget runs out, a cancel request, an unload, a
  /// drop, a job or stop_readers() needs it to.
  [[nodiscard]] planning::VerificationReport verify(std::chrono::milliseconds budget) const;
  /// Stops every running verify with `why` (the daemon is stopping, say).
  void stop_readers(const std::string& why);

  /// The estimate of the roadmap as recorded (its recipe at its sample target; zero without one).
  [[nodiscard]] planning::BuildCost expected_cost() const;

  [[nodiscard]] const std::string& name() const { return name_; }
  [[nodiscard]] const planning::Scene& scene() const { return scene_; }
  /// scene_fingerprint() of the scene as loaded: what a roadmap built here records.
  [[nodiscard]] const std::string& fingerprint() const { return fingerprint_; }
  /// Whether a job is queued or running.
  [[nodiscard]] bool busy() const;
  /// What recovery found at construction (empty when nothing was stored).
  [[nodiscard]] const std::string& recovery_note() const { return recovery_note_; }
  /// What opening cut off the journal's torn tail and where the bytes were kept; empty if nothing.
  [[nodiscard]] const std::string& torn_tail_note() const { return torn_tail_note_; }

 private:
  // Takes job_mutex_ (shared or alone) once no job is queued or running; a job that has just
  // turned idle still holds it while it publishes its last status, so this waits for it briefly.
  // Throws InputError, naming `what`, when a job is queued or running.
  template <typename Lock>
  Lock lock_idle_job(std::string_view what) const;
  std::filesystem::path discard_store(const std::string& aside_why);  // drop (empty why) or set aside
  // `scene`: the scene with the tasks the roadmap will have.
  planning::BuildCost estimate(const planning::Scene& scene, const RoadmapRecipe& recipe,
                               std::uint64_t total_samples) const;
  [[nodiscard]] SessionRecord::Admit admit() const;  // callbacks_.admit_cost of estimate(); none unset
  [[nodiscard]] planning::VerificationReport verify_locked(
      const planning::VerifyKeepGoing& keep_going) const;  // job lock held

  const std::string name_;
  const planning::Scene scene_;
  const std::filesystem::path store_dir_;
  const SessionLimits limits_;
  const SessionCallbacks callbacks_;
  FileSystem& fs_;
  const std::string fingerprint_;  // scene_fingerprint(scene_), recorded in every recipe built here
  mutable std::once_flag free_fraction_once_;
  mutable double free_fraction_ = 1.0;  // of the scene's sampling box, measured on first need

  SessionRecord record_;
  // Whoever touches job_ holds this: run_job and the writers alone, verify and a task's removal
  // shared (a removal's commit is the store's only other writer; removal_mutex_ orders them).
  mutable std::shared_mutex job_mutex_;
  BuildJob job_;
  // Verifies, which a writer (unload, drop, a job) stops before it takes job_mutex_ alone.
  const std::unique_ptr<ReaderGate> readers_ = std::make_unique<ReaderGate>();
  std::mutex removal_mutex_;
  std::string recovery_note_;
  std::string torn_tail_note_;
};

}  // namespace ispars::service
