#pragma once
// What a scene's roadmap is and what is asked of it, under one lock: its state, recipe and
// progress, its tasks, the copy readers are served, and the requests accepted and not yet done.
// Every read is consistent, and every change is one step of the session's life (a request
// accepted, a job taken, a chunk committed, a job ended, a failure, a drop). It runs no builder
// and writes no store: the session's requests and its BuildJob drive it.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/service/build_request.hpp"
#include "ispars/service/inspection_task.hpp"
#include "ispars/service/published_roadmap.hpp"

namespace ispars::service {

/// What a scene's roadmap is doing.
enum class SessionState : std::uint8_t {
  empty,      ///< No roadmap.
  idle,       ///< A roadmap, no job.
  queued,     ///< A job waits for a worker.
  replaying,  ///< Rebuilding the builder from the recipe after a restart (before an extend).
  building,   ///< A job is adding samples.
  failed,     ///< The last job failed; the roadmap is as last committed.
};
[[nodiscard]] std::string_view to_string(SessionState state);

/// A consistent summary of a session.
struct SessionStatus {
  std::string scene;
  SessionState state = SessionState::empty;
  std::optional<RoadmapRecipe> recipe;  ///< Set when there is a roadmap.
  std::uint64_t samples_done = 0;
  std::uint64_t samples_target = 0;
  std::uint64_t version = 0;  ///< Version of the published roadmap.
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t components = 0;
  std::size_t dense_vertices = 0;
  std::size_t dense_edges = 0;
  std::size_t poi_count = 0;      ///< The scene's POIs and its tasks'.
  std::size_t tasks = 0;          ///< Inspection tasks added to the roadmap (not removed).
  std::uint64_t task_events = 0;  ///< Tasks added, plus tasks removed (task_events).
  std::size_t pois_covered = 0;
  std::size_t pois_covered_root = 0;
  std::string last_error;
  /// The published roadmap's generation: the recipe's, or the empty roadmap's after a drop
  /// (0: never built or dropped here).
  std::uint64_t generation = 0;
  /// A build accepted and not started (queued): its recipe (with the generation it makes); its
  /// samples are samples_target. The fleet's status and announcement carry it from acceptance.
  std::optional<RoadmapRecipe> accepted;
};

/// The size of a dense roadmap kept beside the sparse one (zero without one).
struct DenseCounts {
  std::size_t vertices = 0;
  std::size_t edges = 0;
};

/// A stored roadmap as a session serves it: its recipe and tasks, the scene with the tasks'
/// POIs, and the published copy (its vertices seeing those POIs).
struct StoredRoadmap {
  RoadmapRecipe recipe;
  std::vector<InspectionTask> tasks;
  std::shared_ptr<const planning::Scene> scene_with_tasks;
  PublishedRoadmap published;
  DenseCounts dense;
};

/// What readers are served, read in one step: the published copy and, with a roadmap, its
/// recipe, the scene it is planned in and its progress.
struct SessionRoadmap {
  PublishedRoadmap published;
  std::optional<RoadmapRecipe> recipe;
  std::shared_ptr<const planning::Scene> scene_with_tasks;
  std::uint64_t samples_done = 0;
  std::uint64_t samples_target = 0;
  DenseCounts dense;
};

/// A job taken from the record to run: a new roadmap's build, an extend, or a task's addition.
struct SessionJob {
  std::optional<RoadmapRecipe> build;  ///< A new roadmap's recipe; none for an extend or a task.
  std::optional<InspectionTask> task;  ///< A task to add (samples is then 0).
  std::uint64_t samples = 0;           ///< Samples to add.
  RoadmapRecipe recipe;                ///< The recipe the job grows.
};

/// One committed chunk of a growth, as the record takes it.
struct ChunkRecord {
  std::optional<RoadmapRecipe> new_recipe;  ///< A new roadmap's first chunk: it replaces the old one.
  std::uint64_t target = 0;                 ///< With new_recipe: the build's sample target.
  std::uint64_t samples = 0;                ///< The roadmap's samples after the chunk.
  std::optional<PublishedRoadmap> copy;     ///< A new copy for readers, when one was taken.
  DenseCounts dense;
};

/// What a cancel reached.
enum class CancelReach : std::uint8_t {
  none,       ///< No job queued or running.
  dequeued,   ///< A queued job, removed before it started.
  signalled,  ///< A running job, which stops after its current chunk (cancelled()).
};

/// A scene's roadmap record (see the file comment). Its queries are safe from any thread.
class SessionRecord {
 public:
  /// Checks a request's cost against the service's budget (throws InputError to refuse it),
  /// called with the record's lock held: it must not call back into the session.
  using Admit =
      std::function<void(const planning::Scene& scene_with_tasks, const RoadmapRecipe& recipe, std::uint64_t samples)>;

  /// An empty record of scene `name` (`scene` as loaded, which must outlive the record);
  /// notify() hands `on_status` the status.
  SessionRecord(std::string name, const planning::Scene& scene, std::function<void(const SessionStatus&)> on_status);

  [[nodiscard]] SessionStatus status() const;
  [[nodiscard]] PublishedRoadmap published() const;
  [[nodiscard]] SessionRoadmap served() const;
  [[nodiscard]] std::vector<InspectionTask> tasks() const;
  /// tasks(), then a task addition acknowledged and not committed yet.
  [[nodiscard]] std::vector<InspectionTask> accepted_tasks() const;
  [[nodiscard]] std::shared_ptr<const planning::Scene> scene_with_tasks() const;
  /// task_events() of the roadmap's tasks.
  [[nodiscard]] std::uint64_t task_events() const;
  /// Whether a job is queued or running.
  [[nodiscard]] bool busy() const;
  /// Whether the running job was asked to stop.
  [[nodiscard]] bool cancelled() const { return cancel_; }
  /// Hands the status to its owner (outside any lock of the record's).
  void notify() const;

  /// Takes over a stored roadmap (none: the scene's empty roadmap) in `state`, with `error` as
  /// the last error: at load (idle), or after a failed job (failed).
  void take_stored(std::optional<StoredRoadmap> stored, SessionState state, std::string error);
  /// The stored roadmap is unusable (`why`): FAILED, nothing served, until a drop or a replace.
  void refuse(std::string why);
  /// The empty roadmap keeps the generation of a drop made before.
  void keep_drop_generation(std::uint64_t generation);

  /// Records a new build of `recipe` (its fingerprint and builder version set): checks it may
  /// start, calls `admit` last, gives it its generation and returns it. InputError naming the
  /// field otherwise (file "request"), nothing changed.
  std::uint64_t accept_build(RoadmapRecipe recipe, const BuildRequest& request, const std::function<void()>& admit);
  /// Records an extend by `samples`; returns the sample target.
  std::uint64_t accept_extend(std::uint64_t samples, const Admit& admit);
  /// Records a task's addition (checked by check_task); returns the task count after it.
  std::size_t accept_task(InspectionTask task, const Admit& admit);
  CancelReach cancel();
  /// Refuses (InputError) an adoption into a scene with a roadmap, tasks or a job.
  void check_adoptable() const;
  /// Gives the empty scene `tasks` (checked), planned in `scene_with_tasks`.
  void adopt_tasks(std::vector<InspectionTask> tasks, std::shared_ptr<const planning::Scene> scene_with_tasks);
  /// The index of live task `name`, and the task events after its removal; InputError when it
  /// cannot be removed now (`store_open`: whether the store is open for writing).
  [[nodiscard]] std::pair<std::size_t, std::uint64_t> check_removal(const std::string& name, bool store_open) const;
  /// Marks task `index` removed (committed); returns the live tasks left.
  std::size_t mark_removed(std::size_t index);
  /// A drop or set-aside begins (InputError when it cannot); returns the empty roadmap's generation.
  std::uint64_t begin_discard();
  /// The discard failed: the record is as before it.
  void end_discard();
  /// The roadmap is gone: the scene is empty, its roadmap of `empty_generation`.
  void discarded(std::uint64_t empty_generation);
  /// Refuses every later request (InputError while a job is queued or running).
  void close();

  /// The queued job, taken to run (state building). None when nothing is queued; `changed`
  /// tells whether a queued job was settled instead (cancelled, or the daemon stopping).
  [[nodiscard]] std::optional<SessionJob> take(bool stopping, bool& changed);
  /// A started build or task shows as accepted until its first commit.
  void start(const SessionJob& job);
  /// The job ended: it is accepted no longer (kept when the daemon stops: resumed at its restart).
  void forget_starting(bool stopping);
  /// The job is in `state` (replaying or building); `target`: the extend's sample target.
  void begin(SessionState state, std::optional<std::uint64_t> target = std::nullopt);
  void record_chunk(ChunkRecord chunk);
  /// Task `task` was committed: the roadmap plans in `scene_with_tasks`, readers get `copy`.
  void record_task(InspectionTask task, std::shared_ptr<const planning::Scene> scene_with_tasks, PublishedRoadmap copy,
                   DenseCounts dense);
  void publish(PublishedRoadmap copy);
  /// Whether the published copy is the roadmap of `generation` at `samples` and `version`.
  [[nodiscard]] bool publishes(std::uint64_t generation, std::uint64_t samples, std::uint64_t version) const;
  /// The job ended (cancelled or stopped, or done): idle.
  void end_job(bool stopping);
  /// A replay stopped (`why`): idle, nothing served changed.
  void interrupt_replay(std::string why);
  /// The job failed (`why`), the roadmap as before: FAILED.
  void fail(std::string why);
  /// A failure that was `why` and only that (a task not added) leaves the scene idle again.
  void settle_failure(const std::string& why);

 private:
  [[nodiscard]] SessionStatus status_locked() const;
  void check_can_start(const char* field) const;  // with mutex_ held
  void check_can_change() const;                  // check_can_start, and no damage; with mutex_ held
  // No roadmap: the scene's empty one of `generation`, no tasks; with mutex_ held.
  void forget_roadmap(std::uint64_t generation);
  [[nodiscard]] std::size_t live_tasks() const;  // with mutex_ held
  [[nodiscard]] const InspectionTask* accepted_task() const;
  [[nodiscard]] SessionState resting_state() const { return recipe_ ? SessionState::idle : SessionState::empty; }

  const std::string name_;
  const planning::Scene& scene_;
  const std::function<void(const SessionStatus&)> on_status_;

  mutable std::mutex mutex_;  // guards everything below
  SessionState state_ = SessionState::empty;
  std::optional<RoadmapRecipe> recipe_;
  std::uint64_t samples_done_ = 0;
  std::uint64_t samples_target_ = 0;
  std::uint64_t pending_samples_ = 0;
  std::optional<RoadmapRecipe> pending_recipe_;  // a queued build's recipe
  std::optional<RoadmapRecipe> starting_build_;  // a started build's, until its first commit
  std::uint64_t starting_samples_ = 0;
  std::optional<InspectionTask> pending_task_;   // a queued task
  std::optional<InspectionTask> starting_task_;  // a started task's, until it is committed
  std::vector<InspectionTask> tasks_;            // the roadmap's tasks, as stored
  std::shared_ptr<const planning::Scene> scene_with_tasks_;
  bool closed_ = false;
  bool discarding_ = false;  // a drop or set aside is removing the store
  std::string last_error_;
  std::string damage_;  // the stored roadmap could not be opened: nothing was read or changed
  DenseCounts dense_;
  PublishedRoadmap published_;
  std::atomic<bool> cancel_{false};
};

}  // namespace ispars::service
