#pragma once
// Durable storage of one scene's roadmap: what it was built from, and every committed step.
//
// A store is a directory holding these files:
// - recipe.json: scene, method, seed and parameters (written once, atomically);
// - snapshot.bin: a compacted commit from version 0 (replaced atomically);
// - journal.old: while a compaction runs, the commits it folds into the snapshot;
// - journal.log: the commits after those (an append-only record file, fsync'ed).
// Compaction runs off the build thread: a commit that finds the journal long renames it to
// journal.old and starts an empty journal.log (two renames, no copy), and a thread of the store's
// own folds snapshot.bin and journal.old into a new snapshot.bin from their bytes on disk, then
// removes journal.old. A crash anywhere in that leaves files that recover the last commit, and
// the next open() finishes the fold. No record size is a wall (record_file.hpp).
// A commit carries the samples drawn so far and what the roadmap and its dense pair gained; a
// task's commit also carries the task (its POIs widen the roadmaps first, then its guards are
// added), so a crash leaves a store before or after the task, never between.
// The recovered roadmaps (BuiltRoadmaps) and the recipe are the whole builder state of every
// method but IRIS-C (resume_roadmap_builder). Builds are deterministic, so IRIS-C's is recipe +
// samples: replaying the recipe to that many samples rebuilds it exactly, and the recovered
// roadmap checks the replay byte for byte.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/roadmap.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/service/inspection_task.hpp"

namespace ispars::service {

/// One durable step of a build.
struct BuildCommit {
  std::uint64_t samples = 0;            ///< Samples drawn in total after this commit.
  RoadmapBatch roadmap;                 ///< What the method's roadmap gained.
  RoadmapBatch dense;                   ///< What the dense pair gained (empty without one).
  std::vector<VertexId> new_dense_ids;  ///< dense_ids() of the roadmap's new vertices.
  /// Inspection tasks added by this commit (a build's first commit carries the scene's tasks):
  /// their POIs take the next ids, before the batches are applied.
  std::vector<InspectionTask> tasks;
  /// Tasks this commit removes, by index in the store's task list (this commit's tasks
  /// included): their POIs keep their ids and leave every target set.
  std::vector<std::uint64_t> removed_tasks;
  /// With tasks added or removed: the store's task events after this commit (task_events; it
  /// orders a task's commit, which draws no sample, after the commits of the same sample count).
  std::uint64_t task_count = 0;

  /// Whether it adds or removes a task (most commits do neither).
  [[nodiscard]] bool changes_tasks() const { return !tasks.empty() || !removed_tasks.empty(); }
};

/// Whether `commit`, found in a journal after a snapshot of `snapshot_samples` samples and
/// `snapshot_task_events` task events, is one the snapshot holds already.
[[nodiscard]] bool snapshot_holds(const BuildCommit& commit, std::uint64_t snapshot_samples,
                                  std::uint64_t snapshot_task_events);

/// A store's task events: one per task added, and one more per task removed.
[[nodiscard]] std::uint64_t task_events(std::span<const InspectionTask> tasks);

/// Folds `commit`'s task changes into `tasks`, the store's tasks before it: its tasks are
/// appended, then those it removes are marked removed. Throws std::runtime_error, changing
/// nothing, when its task count does not follow `tasks`' events, or it removes a task that does
/// not exist or was removed already.
void fold_tasks(std::vector<InspectionTask>& tasks, const BuildCommit& commit);

/// Makes `commit` record `tasks` whole, removed ones marked (a new roadmap's first commit, a
/// compacted snapshot): fold_tasks of it onto no tasks gives `tasks`.
void set_tasks(BuildCommit& commit, std::span<const InspectionTask> tasks);

[[nodiscard]] std::string encode_commit(const BuildCommit& commit);
/// Throws std::runtime_error on a payload that does not parse exactly.
[[nodiscard]] BuildCommit decode_commit(const std::string& payload);

/// The live roadmaps of a build (the builder's own), seen without copying.
struct RoadmapsView {
  std::uint64_t samples = 0;
  const Roadmap* roadmap = nullptr;
  const Roadmap* dense = nullptr;  ///< nullptr without a dense pair.
  std::span<const VertexId> dense_ids;
};

/// A store whose files are damaged beyond a torn journal tail (a corrupt record in the middle,
/// an unusable commit, a damaged snapshot). The message names the file, the byte offset and the
/// problem; the files are left exactly as they were, for inspection.
struct StoreDamage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// What opening a store recovered.
struct StoreRecovery {
  RoadmapRecipe recipe;
  planning::BuiltRoadmaps roadmaps;
  std::size_t journal_commits = 0;  ///< Commits replayed from the journal after the snapshot.
  bool torn_tail = false;           ///< A torn journal tail (an incomplete last record) was cut off.
  std::string tail_problem;
  std::filesystem::path tail_set_aside;  ///< Where the cut bytes were copied (open() only).
  /// The store's inspection tasks, in order. The recovered roadmaps are widened to their POIs,
  /// and the vertices built after each task see its POIs; the ones built before do not yet
  /// (the store has no scene): see_new_pois (poi_visibility.hpp) adds what they see.
  std::vector<InspectionTask> tasks;
};

/// Appends commits to one scene's store and compacts it. One writer: the store directory is
/// locked (flock) while the object lives, so a second RoadmapStore on it fails to open. Every file
/// operation goes through a FileSystem (the disk, or a test's stand-in that can cut the power),
/// which must outlive the store.
class RoadmapStore {
 public:
  ~RoadmapStore();
  RoadmapStore(const RoadmapStore&) = delete;
  RoadmapStore& operator=(const RoadmapStore&) = delete;

  /// Makes a new store for `recipe` at `dir`. When a store is there already (a replacing build),
  /// the new one is made aside and takes its place atomically at its first commit: until then
  /// the old store stays whole, and a crash leaves it as it was.
  static std::unique_ptr<RoadmapStore> create(const std::filesystem::path& dir, const RoadmapRecipe& recipe,
                                              FileSystem& fs = disk());
  /// Opens the store at `dir`, recovering the last committed roadmaps. Throws std::runtime_error
  /// when the recipe or the snapshot is unreadable.
  /// `poi_count` is the scene's number of POIs.
  static std::unique_ptr<RoadmapStore> open(const std::filesystem::path& dir, std::size_t poi_count,
                                            StoreRecovery& recovered, FileSystem& fs = disk());
  /// Reads the store at `dir` without opening it for writing (no lock, nothing cut or written):
  /// what open() would recover. For serving the last commit when the store cannot be written
  /// (a read-only filesystem). Throws as open() does on damage.
  [[nodiscard]] static StoreRecovery read(const std::filesystem::path& dir, std::size_t poi_count,
                                          const FileSystem& fs = disk());
  /// The recipe of the store at `dir` (to find its scene before opening it).
  [[nodiscard]] static RoadmapRecipe read_recipe(const std::filesystem::path& dir, const FileSystem& fs = disk());

  /// Appends a commit durably (the first commit of a replacing store then puts it in place of
  /// the old one). After `compact_every` journal commits, also starts a compaction in the
  /// background (unless one still runs: then at a later commit). Throws std::runtime_error when
  /// the append fails, or when the last compaction failed (the commit is durable all the same;
  /// the files are as the failed compaction left them, which recover every commit).
  void commit(const BuildCommit& commit);
  /// Compacts now and waits for it: snapshot.bin then holds every commit.
  void compact();
  /// Waits for a running compaction to end (rethrows its failure).
  void wait_for_compaction();

  /// Folds the snapshot and the commits of `journal` (a record file of commits) into one commit,
  /// stopping early (throwing RecordWriteStopped) when `keep_going` says so. Reads only.
  /// Throws StoreDamage when a record is damaged or does not continue the snapshot.
  [[nodiscard]] static BuildCommit fold(const std::filesystem::path& dir, const std::function<bool()>& keep_going,
                                        const FileSystem& fs = disk());

  [[nodiscard]] const std::filesystem::path& dir() const { return dir_; }
  [[nodiscard]] const RoadmapRecipe& recipe() const { return recipe_; }
  /// Commits in the journal since the last snapshot.
  [[nodiscard]] std::size_t journal_commits() const { return journal_commits_; }
  void set_compact_every(std::size_t commits) { compact_every_ = commits; }

 private:
  RoadmapStore(std::filesystem::path dir, RoadmapRecipe recipe, FileSystem& fs);
  void take_place();        // a replacing store: swaps itself with the store at replaces_
  void start_compaction();  // rotates the journal (if no journal.old) and starts the fold thread
  void fold_in_background();
  void stop_compaction();  // asks a running fold to stop, and joins it
  FileSystem& fs_;
  std::filesystem::path dir_;
  std::filesystem::path replaces_;  // a replacing store before its first commit: the store it replaces
  RoadmapRecipe recipe_;
  std::unique_ptr<RecordFileWriter> journal_;
  std::size_t journal_commits_ = 0;
  std::uint64_t samples_ = 0;      // of the last commit (for head)
  std::uint64_t task_events_ = 0;  // after the last commit (for head)
  std::size_t compact_every_ = 64;
  std::unique_ptr<FileSystem::Lock> lock_;
  std::thread compactor_;
  std::atomic<bool> compacting_{false};       // the fold thread runs
  std::atomic<bool> stop_compacting_{false};  // asked to stop (close, unload, SIGTERM)
  std::mutex compaction_mutex_;
  std::string compaction_error_;  // the last fold's failure, thrown by the next commit
};

/// The commit taking the build from the given versions of its roadmaps to `now`.
[[nodiscard]] BuildCommit commit_since(const RoadmapsView& now, std::uint64_t roadmap_version,
                                       std::uint64_t dense_version);
/// A view of stored roadmaps.
[[nodiscard]] RoadmapsView view_of(const planning::BuiltRoadmaps& roadmaps);

/// Applies a commit to recovered roadmaps (throws std::runtime_error when it does not continue
/// them). A commit with tasks widens the roadmaps to their POIs first.
void apply_commit(planning::BuiltRoadmaps& roadmaps, const BuildCommit& commit);

/// What a store's last commit holds, as its `head` file says: a hint written after each commit
/// (and when the store is opened), so a daemon can announce its stored roadmaps without reading
/// them. It may lag the journal after a power cut (not fsync'ed), never lead it.
struct StoreHead {
  std::uint64_t generation = 0;
  std::uint64_t samples = 0;
  /// journal.log's length once that commit was durable (0: unknown, as in heads older than it).
  /// Every byte before it was acknowledged: a record that fails its checksum there is damage,
  /// never a crash's torn tail.
  std::uint64_t journal_bytes = 0;
  /// The store's task events (task_events) after that commit: the fleet weighs a copy by them
  /// after its samples (0 in heads older than the field).
  std::uint64_t task_events = 0;
};
/// Writes `head` by a rename; with `durable`, fsync'ed (file and directory) before it returns, and
/// throws on failure; otherwise a failure is ignored (a hint).
void write_store_head(const std::filesystem::path& dir, const StoreHead& head, FileSystem& fs = disk(),
                      bool durable = false);
/// The store's head; nothing when it has none (a store older than the file) or it is unreadable.
[[nodiscard]] std::optional<StoreHead> read_store_head(const std::filesystem::path& dir, const FileSystem& fs = disk());

/// Why the store in `dir` cannot be served, found without reading it whole (for the fleet's
/// announcement, which must not offer a copy that a takeover would fail to open): a file of it
/// that does not start with its format's magic, or a journal shorter than its head says was
/// durable. Empty when neither; recovery checks every record.
[[nodiscard]] std::string store_quick_problem(const std::filesystem::path& dir);

/// Why the store in `dir` cannot be served, found by reading every record of its snapshot and
/// journals (framing and checksums, not the commits' contents) as recovery would, without opening
/// it: a record refused, a snapshot that is not one whole record, a rotated journal that is not
/// whole, or a bad record within what its head says was durable. A crash's torn tail is no
/// problem. Empty when none. Reads only; holds one file in memory at a time (twice its size).
[[nodiscard]] std::string store_scrub_problem(const std::filesystem::path& dir, const FileSystem& fs = disk());

/// Keeps a store the fleet superseded: renames it, whole, to DATA_DIR/.aside/NAME-gGEN-SAMPLES
/// (a further ".N" when taken) with `why` in its aside.txt, durably. Returns where it went.
/// Nothing at start or later removes it: an operator reads it and deletes it.
std::filesystem::path set_aside_store(const std::filesystem::path& dir, const std::string& why,
                                      FileSystem& fs = disk());

/// Removes a store: renames it aside (atomic), then deletes it. Leftovers of an interrupted
/// creation or removal (".new-NAME", ".dropped-NAME") are removed by remove_dropped_stores().
void drop_store(const std::filesystem::path& dir, FileSystem& fs = disk());

/// Marks (or unmarks) the store in `dir` as unloaded: a daemon that restarts does not reload an
/// unloaded scene's stored roadmap until the scene is loaded again. Durable (fsync'ed). Nothing
/// to mark (or unmark) when `dir` holds no store.
void mark_unloaded(const std::filesystem::path& dir, bool unloaded, FileSystem& fs = disk());
/// Whether the store in `dir` is marked unloaded.
[[nodiscard]] bool marked_unloaded(const std::filesystem::path& dir, const FileSystem& fs = disk());
/// At start: removes what an interrupted drop or creation left (".dropped-NAME", a staging
/// ".new-NAME"), and puts in place a replacing store caught between the two renames of the
/// fallback swap (".new-NAME" with a commit and no "NAME").
void remove_dropped_stores(const std::filesystem::path& data_dir, FileSystem& fs = disk());

}  // namespace ispars::service
