#pragma once
// The roadmap service without its transport: the scenes a daemon holds (a SceneRegistry of one
// RoadmapSession each), every operation a client may ask for in typed form, build jobs and tours
// on the service's own worker pools, and tour admission. The DDS layer (server/daemon/) decodes a request, calls one of
// these functions, and encodes what it returns; unit tests call them directly.
//
// Every operation checks its arguments here, once, and throws InputError (file "request", the
// field named) for a bad one; no operation that throws has changed anything.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ispars/service/job_queue.hpp"
#include "ispars/service/memory_budget.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/scene_fingerprints.hpp"
#include "ispars/service/scene_registry.hpp"
#include "ispars/service/snapshot_cache.hpp"
#include "ispars/service/store_scrub.hpp"
#include "ispars/service/tour_desk.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::service {

struct PendingJob;  // pending_jobs.hpp

/// Where a service finds scenes and keeps roadmaps, and what it allows.
struct ServiceSettings {
  std::string server_id;             ///< This service's name in messages ("daemon X").
  std::filesystem::path scene_dir;   ///< The only directory scenes load from.
  std::filesystem::path data_dir;    ///< One store directory per scene.
  SessionLimits limits;              ///< Per session: samples per request, compaction, build threads.
  unsigned build_workers = 2;        ///< Builds running at once (each on its own thread).
  unsigned tour_workers = 2;         ///< Tours running at once.
  std::size_t tours_per_worker = 2;  ///< Tours admitted (queued or running) per tour worker.
  /// Memory the roadmaps of all loaded scenes may be expected to hold together at their peaks, with
  /// the snapshot encodings and tours running (memory_budget.hpp); what would not fit is refused.
  double memory_budget_bytes = std::numeric_limits<double>::infinity();
  /// How often the stores no session holds are checked whole for damage (StoreScrub), each once
  /// per version of its files; 0: never (unit tests that do not test it).
  std::chrono::milliseconds scrub_period{0};
};

/// A scene the service can load, as listed.
struct SceneListing {
  std::string name;
  bool loaded = false;
  bool has_roadmap = false;  ///< Loaded with a roadmap, or not loaded with a store on disk.
};

/// A roadmap the service can serve, as the fleet weighs it (docs/fleet.md).
struct ServedRoadmap {
  std::string scene;
  std::uint64_t generation = 0;   ///< Of the roadmap (of the empty one after a drop; 0: never built).
  std::uint64_t samples = 0;      ///< Committed.
  std::uint64_t target = 0;       ///< Accepted: a queued or running job's target, else `samples`.
  std::string fingerprint;        ///< Of the scene file it was built on (empty when unknown).
  bool held = false;              ///< Loaded here; else stored only.
  std::uint64_t task_events = 0;  ///< Its tasks added and removed: weighed after the samples.
};

/// A stored roadmap this service cannot serve, and why (another builder version, an unreadable
/// recipe): never weighed by the fleet, named in the scenes list.
struct UnservableStore {
  std::string scene;
  std::string why;
};

/// The stores of a data directory, in one pass: every scene with a stored roadmap, sorted (loaded
/// or not); those not loaded (`loaded` names those that are) as the fleet weighs them; and those
/// that cannot be served: another builder version, files that do not open (store_quick_problem),
/// or, given `current`, a scene file whose fingerprint now differs from the one the copy was
/// built on (or that no longer loads). Reads each store's recipe.json, head and first bytes.
struct StoredListing {
  std::vector<std::string> scenes;
  std::vector<ServedRoadmap> served;
  std::vector<UnservableStore> unservable;
};
/// `scrubbed` names the damage a whole read of a scene's store found (StoreScrub), if given.
[[nodiscard]] StoredListing list_stored_roadmaps(const std::filesystem::path& data_dir,
                                                 const std::vector<std::string>& loaded,
                                                 SceneFingerprints* current = nullptr,
                                                 const std::function<std::string(const std::string&)>& scrubbed = {});

/// What the service tells its owner (the transport). Called on the thread that caused the event.
struct ServiceEvents {
  /// A committed batch of a scene's roadmap (on the job's thread, in order).
  std::function<void(const std::string& scene, const RoadmapBatch& batch, std::uint64_t generation,
                     std::uint64_t samples, std::size_t poi_count)>
      on_commit;
  /// A loaded scene's status changed.
  std::function<void(const RoadmapSession& session)> on_status;
  /// A scene is no longer held (unloaded, given up to its owner, or the service stopped);
  /// `given_up`: to another daemon, which publishes the scene's statuses from now on.
  std::function<void(const std::string& scene, bool given_up)> on_unloaded;
  /// The set of loaded scenes changed.
  std::function<void()> on_scenes_changed;
  /// A tour of a scene finished (on its worker's thread, before its reply is sent).
  std::function<void(const std::string& scene, const TourOutcome& outcome)> on_tour;
  /// Called before a scene is loaded; throws InputError (naming the owner) when this service may
  /// not hold it. Each successful claim is matched by exactly one `release`.
  std::function<void(const std::string& scene)> claim;
  /// A claimed scene is not held any more: its load failed, it was unloaded or given up, or the
  /// service stopped.
  std::function<void(const std::string& scene)> release;
};

/// A verification and whether the roadmap's method promises Invariant 1 (only Inspection-SPARS).
struct VerifyOutcome {
  planning::VerificationReport report;
  bool invariant_promised = false;
  /// Problems the method promises to avoid (0: verified).
  [[nodiscard]] std::uint64_t violations() const;
};

/// What a cancel stopped.
struct CancelOutcome {
  bool build_cancelled = false;
  std::size_t tours_stopped = 0;
};

/// The scenes one daemon holds and every operation on them, safe to call from many threads.
class RoadmapService {
 public:
  /// A service over `settings` with no scene loaded. Throws std::runtime_error when the scene
  /// directory does not exist. Removes leftovers of dropped stores. Every file of the data
  /// directory is written and read through `fs` (a test's PowerCutFileSystem stands in for the disk).
  RoadmapService(ServiceSettings settings, ServiceEvents events, FileSystem& fs = disk());
  /// Same as stop().
  ~RoadmapService();
  RoadmapService(const RoadmapService&) = delete;
  RoadmapService& operator=(const RoadmapService&) = delete;

  /// Loads every scene with a stored roadmap (a failure is logged and skips that scene).
  void load_stored_roadmaps();
  /// Stops: tours stop early and report their best, builds commit their current chunk and stop,
  /// queued jobs are dropped, and every loaded scene is reported unloaded. Idempotent.
  void stop();

  // Queries.
  [[nodiscard]] std::vector<SceneListing> list_scenes() const;
  [[nodiscard]] std::vector<std::string> loaded_scenes() const;
  [[nodiscard]] SessionStatus stats(const std::string& scene) const;
  [[nodiscard]] planning::RoadmapPath path(const std::string& scene, const Vec3& from, const Vec3& to) const;
  /// Chunk `chunk_index` of the roadmap at `version` of `generation` with `poi_count` POIs
  /// (version 0: the latest; a task adds POIs without a new version).
  [[nodiscard]] SnapshotSlice snapshot(const std::string& scene, std::uint64_t version, std::uint64_t generation,
                                       std::uint32_t chunk_index, std::size_t poi_count = 0);
  [[nodiscard]] VerifyOutcome verify(const std::string& scene) const;
  /// Admits a tour and runs it on a tour worker. Throws InputError for bad arguments, a scene
  /// without a roadmap, or when the tour queue is full ("busy").
  void start_tour(const std::string& scene, TourRequest request, TourCallbacks callbacks);

  // Changes.
  /// Loads `scene` (with its stored roadmap); returns its session and whether it was loaded by
  /// this call (false: it already was).
  std::pair<std::shared_ptr<RoadmapSession>, bool> load(const std::string& scene);
  void unload(const std::string& scene);
  /// Gives `scene` up to the daemon that owns it: stops its build (after the current chunk) and
  /// its tours, waits for them, and unloads it without an UNLOADED status (the owner's statuses
  /// are the scene's now). Unlike unload() the stored roadmap stays eligible for reloading at
  /// restart. Returns at once when the scene is not loaded (or was unloaded meanwhile), and
  /// without unloading when `give_up` becomes true (the daemon is stopping).
  void yield(const std::string& scene, const std::atomic<bool>& give_up);
  /// Stops the running verifies of `scene` (if loaded) with `why`.
  void stop_readers(const std::string& scene, const std::string& why);
  /// Stops the running verifies of every scene with `why`, and from now on every snapshot encoding
  /// at its next slice (the daemon is stopping).
  void stop_all_readers(const std::string& why);
  /// How long yield() tries before it leaves the scene as it is (for the fleet's next pass).
  static constexpr std::chrono::seconds kYieldWait{10};
  /// The roadmaps of the loaded scenes, as the fleet weighs them (live: committed samples and
  /// accepted targets).
  [[nodiscard]] std::vector<ServedRoadmap> held_roadmaps() const;
  /// Sets the roadmap of a loaded scene aside (RoadmapSession::set_aside); returns where it went.
  std::filesystem::path set_aside(const std::string& scene, const std::string& why);
  /// RoadmapSession::adopt_tasks of a loaded scene.
  void adopt_tasks(const std::string& scene, std::vector<InspectionTask> tasks);
  /// Queues a build or an extend, first recorded in the data directory (pending_jobs.hpp): a
  /// restart resumes it. Throws InputError naming the field when the session refuses it.
  void build(const std::string& scene, const BuildRequest& request);
  void extend(const std::string& scene, std::uint64_t samples);
  /// Queues the addition of an inspection task (RoadmapSession::request_task), recorded as a
  /// build is; returns the scene's task count after it.
  std::size_t add_task(const std::string& scene, InspectionTask task);
  /// Removes an inspection task at once (RoadmapSession::remove_task); returns the tasks left.
  std::size_t remove_task(const std::string& scene, const std::string& name);
  /// Resumes the jobs recorded and not finished when the daemon last stopped (called once, after
  /// load_stored_roadmaps): an extend, or a build that committed, goes on to its target; a build
  /// that never committed starts again. A job whose scene is not this daemon's, or that is
  /// refused now, is logged and forgotten.
  void resume_pending_jobs();
  CancelOutcome cancel(const std::string& scene);
  void drop(const std::string& scene);

  /// The loaded session of `scene`; InputError naming the scene when it is not loaded.
  [[nodiscard]] std::shared_ptr<RoadmapSession> session(const std::string& scene) const;
  [[nodiscard]] const ServiceSettings& settings() const { return settings_; }
  /// The memory budget's reservations and leases (for metrics).
  [[nodiscard]] const MemoryBudget& budget() const { return *budget_; }
  /// The damage the background check found in `scene`'s store as it is now (StoreScrub); empty
  /// when none, or when the check is off (ServiceSettings::scrub_period).
  [[nodiscard]] std::string scrub_problem(const std::string& scene) const;

 private:
  std::shared_ptr<RoadmapSession> session_or_null(const std::string& scene) const;
  std::shared_ptr<RoadmapSession> open_session(const std::string& scene);
  void forget(const std::string& scene, bool given_up);  // erases a closed session; events
  // Jobs (roadmap_service_jobs.cpp): accepted and recorded as one step by the JobQueue.
  void accept(const std::string& scene, const std::optional<BuildRequest>& build, std::uint64_t samples,
              std::uint32_t attempts);
  std::size_t accept_task(const std::string& scene, InspectionTask task, std::uint32_t attempts);

  const ServiceSettings settings_;
  const ServiceEvents events_;
  FileSystem& fs_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> readers_stopped_{false};  // stop_all_readers was called: the daemon is stopping

  SceneRegistry scenes_;

  const std::shared_ptr<MemoryBudget> budget_;
  SnapshotCache snapshots_;            // the budget's reclaimer drops its kept encodings
  std::unique_ptr<StoreScrub> scrub_;  // made last in the constructor, stopped first in stop()

  JobQueue jobs_;
  TourDesk tours_;
};

}  // namespace ispars::service
