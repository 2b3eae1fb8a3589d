#include "ispars/service/roadmap_store.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "ispars/roadmap/sealed_file.hpp"
#include "roadmap_store_damage.hpp"
#include "roadmap_store_files.hpp"

namespace ispars::service {
namespace {

using namespace store_files;

planning::BuiltRoadmaps empty_roadmaps(const RoadmapRecipe& recipe, std::size_t poi_count) {
  planning::BuiltRoadmaps r{0, Roadmap(poi_count), std::nullopt, {}};
  if (has_dense_pair(recipe.method)) r.dense.emplace(poi_count);
  return r;
}

}  // namespace

RoadmapsView view_of(const planning::BuiltRoadmaps& r) {
  return {r.samples, &r.roadmap, r.dense ? &*r.dense : nullptr, r.dense_ids};
}

BuildCommit commit_since(const RoadmapsView& now, std::uint64_t roadmap_version, std::uint64_t dense_version) {
  BuildCommit commit;
  commit.samples = now.samples;
  commit.roadmap = batch_since(*now.roadmap, roadmap_version);
  if (now.dense != nullptr) {
    commit.dense = batch_since(*now.dense, dense_version);
    const std::size_t added = commit.roadmap.positions.size();
    commit.new_dense_ids.assign(now.dense_ids.end() - static_cast<std::ptrdiff_t>(added), now.dense_ids.end());
  }
  return commit;
}

void apply_commit(planning::BuiltRoadmaps& r, const BuildCommit& commit) {
  if (commit.samples < r.samples) throw std::runtime_error("commit goes back in samples");
  const bool dense_present = r.dense.has_value();
  if (!dense_present && (!commit.dense.changes.empty() || !commit.new_dense_ids.empty())) {
    throw std::runtime_error("commit has a dense part but the method has no dense roadmap");
  }
  if (dense_present && commit.new_dense_ids.size() != commit.roadmap.positions.size()) {
    throw std::runtime_error("commit has " + std::to_string(commit.new_dense_ids.size()) + " dense ids for " +
                             std::to_string(commit.roadmap.positions.size()) + " new vertices");
  }
  // Check everything before changing anything, so a bad commit leaves the roadmaps as they were.
  if (r.roadmap.version() != commit.roadmap.from_version ||
      (dense_present && r.dense->version() != commit.dense.from_version)) {
    throw std::runtime_error("commit does not continue the stored roadmaps");
  }
  std::size_t task_pois = 0;
  for (const InspectionTask& task : commit.tasks) task_pois += task.pois.size();
  if (task_pois > 0) {
    // Widening changes no vertex, edge or version: a commit refused below leaves only wider rows.
    r.roadmap.widen_pois(r.roadmap.poi_count() + task_pois);
    if (dense_present) r.dense->widen_pois(r.dense->poi_count() + task_pois);
  }
  check_batch(r.roadmap, commit.roadmap);
  if (dense_present) {
    check_batch(*r.dense, commit.dense);
    const std::size_t dense_after = r.dense->vertex_count() + commit.dense.positions.size();
    for (const VertexId id : commit.new_dense_ids) {
      if (id >= dense_after) throw std::runtime_error("commit dense id out of range");
    }
  }
  // Every part fits: applied in place, the task's POIs first (its guards see them) (a copy of the dense roadmap per
  // commit made a restart's recovery cost its size times its journal's length).
  apply_checked_batch(r.roadmap, commit.roadmap);
  if (dense_present) {
    apply_checked_batch(*r.dense, commit.dense);
    r.dense_ids.insert(r.dense_ids.end(), commit.new_dense_ids.begin(), commit.new_dense_ids.end());
  }
  r.samples = commit.samples;
}

RoadmapStore::RoadmapStore(std::filesystem::path dir, RoadmapRecipe recipe, FileSystem& fs)
    : fs_(fs), dir_(std::move(dir)), recipe_(std::move(recipe)) {
  // One writer per store, across threads and processes: a second open fails instead of
  // truncating or renaming files under the first.
  lock_ = fs_.lock(dir_);
  if (!lock_) throw std::runtime_error("store " + dir_.string() + " is in use by another writer");
}

RoadmapStore::~RoadmapStore() {
  stop_compaction();
  journal_.reset();
}

std::unique_ptr<RoadmapStore> RoadmapStore::create(const std::filesystem::path& dir, const RoadmapRecipe& recipe,
                                                   FileSystem& fs) {
  // Build it aside and rename it into place, so a crash leaves no half-made store. Scene names
  // never start with '.', so the staging name can never be another scene's store.
  const std::filesystem::path staging = dir.parent_path() / (".new-" + dir.filename().string());
  fs.remove_all(staging);
  fs.create_directories(staging);
  write_file_atomically(recipe_path(staging), recipe_to_json(recipe), fs);
  RecordFileWriter(journal_path(staging), kJournal, 0, fs);
  const bool replacing = fs.exists(dir);
  if (!replacing) {
    fs.rename(staging, dir);
    fsync_directory_of(dir, fs);
  }
  const std::filesystem::path& at = replacing ? staging : dir;
  auto store = std::unique_ptr<RoadmapStore>(new RoadmapStore(at, recipe, fs));
  store->journal_ = std::make_unique<RecordFileWriter>(journal_path(at), kJournal, kJournal.magic().size(), fs);
  if (replacing) store->replaces_ = dir;
  return store;
}

void RoadmapStore::take_place() {
  // One atomic exchange of the two directories: the path names the old store until the call
  // and the new one after it, never neither. The old one is then removed from the staging name.
  const std::filesystem::path staging = dir_;
  if (!fs_.exchange(staging, replaces_)) {
    // A filesystem without RENAME_EXCHANGE: the old store aside, then the new one in place. A
    // crash in between leaves only .new-NAME, with its first commit, which remove_dropped_stores()
    // puts in place at the next start.
    drop_store(replaces_, fs_);
    fs_.rename(staging, replaces_);
  }
  fsync_directory_of(replaces_, fs_);
  fs_.remove_all(staging);  // the old store, if exchanged
  dir_ = replaces_;
  replaces_.clear();
}

RoadmapRecipe RoadmapStore::read_recipe(const std::filesystem::path& dir, const FileSystem& fs) {
  const std::optional<std::string> text = fs.read(recipe_path(dir));
  if (!text) throw std::runtime_error("store " + dir.string() + " has no recipe.json");
  try {
    return recipe_from_json(*text);
  } catch (const std::runtime_error& e) {  // damaged or edited: named, and nothing is touched
    throw StoreDamage(fmt::format("{}: {}", recipe_path(dir).string(), e.what()));
  }
}

namespace {

// Replays the snapshot, journal.old (while a compaction runs) and journal.log of the store at
// `dir` into `recovered`; journal.log's valid length. Reads only. (A compaction of the same store
// must not run meanwhile: it removes journal.old once the snapshot holds it.)
std::uint64_t recover_into(const std::filesystem::path& dir, std::size_t poi_count, StoreRecovery& recovered,
                           const FileSystem& fs) {
  recovered.roadmaps = empty_roadmaps(recovered.recipe, poi_count);
  planning::BuiltRoadmaps& r = recovered.roadmaps;
  const bool has_snapshot = fs.exists(snapshot_path(dir));
  if (has_snapshot) {
    const RecordReplay snapshot = read_record_file(
        snapshot_path(dir), kSnapshot, [](const std::string&) { return std::string(); }, fs);
    if (auto problem = snapshot_damage(dir, snapshot)) throw StoreDamage(*problem);
    const BuildCommit whole = decode_commit(snapshot.payloads.front());
    apply_commit(r, whole);
    fold_tasks(recovered.tasks, whole);
  }
  // Journal commits the snapshot already holds are left from a compaction that crashed between
  // writing the snapshot and removing journal.old (or, in stores of older versions, resetting the
  // journal): skip them. Every commit draws at least one sample, so the sample count (not a
  // roadmap version, which a chunk may leave unchanged) tells them apart.
  const std::uint64_t snapshot_samples = r.samples;
  const std::uint64_t snapshot_tasks = task_events(recovered.tasks);
  std::size_t commits = 0;
  const auto replay = [&](const std::filesystem::path& path) {
    commits = 0;
    return read_record_file(
        path, kJournal,
        [&](const std::string& payload) {
          try {
            const BuildCommit commit = decode_commit(payload);
            if (has_snapshot && snapshot_holds(commit, snapshot_samples, snapshot_tasks)) return std::string();
            // A task's commit is checked before the roadmaps change (the others leave the tasks be:
            // no copy of every task's POIs per commit).
            std::vector<InspectionTask> tasks;
            if (commit.changes_tasks()) {
              tasks = recovered.tasks;
              fold_tasks(tasks, commit);
            }
            apply_commit(r, commit);
            if (commit.changes_tasks()) recovered.tasks = std::move(tasks);
            ++commits;
            return std::string();
          } catch (const std::runtime_error& e) {
            return std::string("unusable commit: ") + e.what();
          }
        },
        fs, RecordKeep::count);
  };
  if (fs.exists(old_journal_path(dir))) {
    // A rotated journal was whole: anything but whole records in it is damage.
    const RecordReplay old = replay(old_journal_path(dir));
    if (old.torn_tail) throw StoreDamage(damage_text(old_journal_path(dir), old, fs));
  }
  const RecordReplay journal = replay(journal_path(dir));
  // Not a crash's torn tail: stop before the writer would cut it, and say where.
  if (const auto damaged = journal_damage(dir, journal, fs))
    throw StoreDamage(damage_text(journal_path(dir), *damaged, fs));
  recovered.journal_commits = commits;
  recovered.torn_tail = journal.torn_tail;
  recovered.tail_problem = journal.tail_problem;
  return journal.valid_bytes;
}

// recover_into, with a file of unknown magic reported as damage at byte 0 (a flipped bit there
// is not a file of another program: it is left as it is and named).
std::uint64_t recover_checked(const std::filesystem::path& dir, std::size_t poi_count, StoreRecovery& recovered,
                              const FileSystem& fs) {
  try {
    return recover_into(dir, poi_count, recovered, fs);
  } catch (const RecordMagicMismatch& e) {
    throw StoreDamage(
        fmt::format("{} is damaged at byte 0: {}; left untouched for inspection (drop the scene's "
                    "roadmap, or build with replace, to discard it)",
                    dir.string(), e.what()));
  }
}

}  // namespace

std::unique_ptr<RoadmapStore> RoadmapStore::open(const std::filesystem::path& dir, std::size_t poi_count,
                                                 StoreRecovery& recovered, FileSystem& fs) {
  auto store = std::unique_ptr<RoadmapStore>(new RoadmapStore(dir, read_recipe(dir, fs), fs));  // locks first
  recovered.recipe = store->recipe_;
  const std::uint64_t valid_bytes = recover_checked(dir, poi_count, recovered, fs);
  store->journal_ = std::make_unique<RecordFileWriter>(journal_path(dir), kJournal, valid_bytes, fs);
  recovered.tail_set_aside = store->journal_->set_aside();
  store->journal_commits_ = recovered.journal_commits;
  store->samples_ = recovered.roadmaps.samples;
  store->task_events_ = task_events(recovered.tasks);
  write_store_head(dir, {recovered.recipe.generation, recovered.roadmaps.samples, valid_bytes, store->task_events_},
                   fs);  // mends a stale hint
  // A compaction that did not finish (a crash, a stop, a failure): finish it now.
  if (fs.exists(old_journal_path(dir))) store->fold_in_background();
  return store;
}

StoreRecovery RoadmapStore::read(const std::filesystem::path& dir, std::size_t poi_count, const FileSystem& fs) {
  StoreRecovery recovered;
  recovered.recipe = read_recipe(dir, fs);
  (void)recover_checked(dir, poi_count, recovered, fs);
  return recovered;
}

void RoadmapStore::commit(const BuildCommit& commit) {
  journal_->append(encode_commit(commit));
  ++journal_commits_;
  if (!replaces_.empty()) take_place();
  samples_ = commit.samples;
  if (commit.changes_tasks()) task_events_ = commit.task_count;
  write_store_head(dir_, {recipe_.generation, samples_, journal_->size(), task_events_},
                   fs_);                    // after the commit is durable
  if (!compacting_) wait_for_compaction();  // joins a finished fold; throws its failure
  if (journal_commits_ >= compact_every_) start_compaction();
}

void write_store_head(const std::filesystem::path& dir, const StoreHead& head, FileSystem& fs, bool durable) {
  // Renamed into place, not fsync'ed after commits: a hint that may lag the journal after a power
  // cut, never lead it (it is written after the commit it names is durable).
  const std::filesystem::path tmp = dir / "head.tmp";
  try {
    auto file = fs.open(tmp, FileSystem::Open::truncated);
    file->append(
        seal_text(fmt::format("{} {} {} {}\n", head.generation, head.samples, head.journal_bytes, head.task_events)));
    if (durable) file->sync();
    file.reset();
    fs.rename(tmp, dir / "head");
    if (durable) fsync_directory_of(dir / "head", fs);
  } catch (const std::runtime_error&) {
    if (durable) throw;
    // A hint: the commit stands without it.
  }
}

std::optional<StoreHead> read_store_head(const std::filesystem::path& dir, const FileSystem& fs) {
  const std::optional<std::string> text = fs.read(dir / "head");
  if (!text) return std::nullopt;
  const SealedText sealed = open_sealed_text(*text);
  if (sealed.seal == Seal::broken) {
    spdlog::error("{} fails its checksum (changed or damaged): read as no head", (dir / "head").string());
    return std::nullopt;
  }
  std::istringstream in(sealed.body);
  StoreHead head;
  if (!(in >> head.generation >> head.samples)) return std::nullopt;
  if (!(in >> head.journal_bytes)) head.journal_bytes = 0;  // a head older than the field
  if (!(in >> head.task_events)) head.task_events = 0;      // older than this one
  return head;
}

std::filesystem::path set_aside_store(const std::filesystem::path& dir, const std::string& why, FileSystem& fs) {
  const StoreHead head = read_store_head(dir, fs).value_or(StoreHead{});
  const std::filesystem::path aside_dir = dir.parent_path() / ".aside";
  if (fs.create_directories(aside_dir)) fsync_directory_of(aside_dir, fs);
  std::filesystem::path target =
      aside_dir / fmt::format("{}-g{}-{}", dir.filename().string(), head.generation, head.samples);
  for (int n = 2; fs.exists(target); ++n) {
    target = aside_dir / fmt::format("{}-g{}-{}.{}", dir.filename().string(), head.generation, head.samples, n);
  }
  write_file_atomically(dir / "aside.txt", why + "\n", fs);
  fs.rename(dir, target);
  // Its new name first: a cut between the two syncs then leaves it under both names, not neither.
  fsync_directory_of(target, fs);
  fsync_directory_of(dir, fs);
  return target;
}

void drop_store(const std::filesystem::path& dir, FileSystem& fs) {
  if (!fs.exists(dir)) return;
  const std::filesystem::path aside = dir.parent_path() / (".dropped-" + dir.filename().string());
  fs.remove_all(aside);
  fs.rename(dir, aside);
  fsync_directory_of(dir, fs);
  fs.remove_all(aside);
}

void mark_unloaded(const std::filesystem::path& dir, bool unloaded, FileSystem& fs) {
  const std::filesystem::path marker = dir / "unloaded";
  if (unloaded) {
    if (!fs.exists(recipe_path(dir))) return;  // no stored roadmap to keep out
    write_file_atomically(marker, "unloaded by request; a load request loads it again\n", fs);
  } else if (fs.remove(marker)) {
    fsync_directory_of(marker, fs);
  }
}

bool marked_unloaded(const std::filesystem::path& dir, const FileSystem& fs) { return fs.exists(dir / "unloaded"); }

void remove_dropped_stores(const std::filesystem::path& data_dir, FileSystem& fs) {
  for (const std::string& name : fs.list(data_dir)) {
    const std::filesystem::path entry = data_dir / name;
    if (name.rfind(".dropped-", 0) == 0) {
      fs.remove_all(entry);
    } else if (name.rfind(".new-", 0) == 0) {
      // A replacing store caught between the two renames of the fallback: it holds its first
      // commit (the journal longer than its header) and its old store is gone, so it is the truth.
      const std::filesystem::path target = data_dir / name.substr(5);
      const std::uint64_t journal_size = fs.file_size(journal_path(entry)).value_or(0);
      if (!fs.exists(target) && journal_size > kJournal.magic().size()) {
        fs.rename(entry, target);
        fsync_directory_of(target, fs);
      } else {
        fs.remove_all(entry);  // a staging store that never took its place
      }
    }
  }
}

}  // namespace ispars::service
