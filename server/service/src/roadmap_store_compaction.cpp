// Compaction of a roadmap store off the build thread: the journal is rotated to journal.old, and
// a thread folds snapshot.bin and journal.old into a new snapshot.bin from their bytes on disk.

#include <fmt/format.h>

#include <filesystem>
#include <iterator>
#include <stdexcept>

#include "ispars/service/roadmap_store.hpp"
#include "roadmap_store_files.hpp"

namespace ispars::service {
namespace {

using namespace store_files;

template <class T>
void append_all(std::vector<T>& to, std::vector<T>&& from) {
  to.insert(to.end(), std::make_move_iterator(from.begin()), std::make_move_iterator(from.end()));
}

// Appends `next` to `whole`, which it must continue.
void append_batch(RoadmapBatch& whole, RoadmapBatch&& next) {
  if (next.from_version != whole.to_version) {
    throw std::runtime_error(
        fmt::format("it starts at version {}, the roadmap is at {}", next.from_version, whole.to_version));
  }
  whole.to_version = next.to_version;
  append_all(whole.changes, std::move(next.changes));
  append_all(whole.positions, std::move(next.positions));
  append_all(whole.visible, std::move(next.visible));
  append_all(whole.edges, std::move(next.edges));
}

}  // namespace

BuildCommit RoadmapStore::fold(const std::filesystem::path& dir, const std::function<bool()>& keep_going,
                               const FileSystem& fs) {
  const auto stop_if_asked = [&] {
    if (keep_going && !keep_going()) throw RecordWriteStopped("compacting " + dir.string() + " was stopped");
  };
  BuildCommit whole;
  const bool has_snapshot = fs.exists(snapshot_path(dir));
  if (has_snapshot) {
    const RecordReplay snapshot = read_record_file(
        snapshot_path(dir), kSnapshot, [](const std::string&) { return std::string(); }, fs);
    if (snapshot.payloads.size() != 1 || snapshot.torn_tail) {
      throw StoreDamage(fmt::format("{} is damaged at byte {}: {}; left untouched for inspection",
                                    snapshot_path(dir).string(), snapshot.valid_bytes,
                                    snapshot.tail_problem.empty() ? "not exactly one record" : snapshot.tail_problem));
    }
    try {
      whole = decode_commit(snapshot.payloads.front());
    } catch (const std::runtime_error& e) {
      throw StoreDamage(
          fmt::format("{} is damaged: {}; left untouched for inspection", snapshot_path(dir).string(), e.what()));
    }
  }
  stop_if_asked();
  const std::uint64_t snapshot_samples = whole.samples;
  std::vector<InspectionTask> tasks;
  try {
    fold_tasks(tasks, whole);
  } catch (const std::runtime_error& e) {
    throw StoreDamage(
        fmt::format("{} is damaged: {}; left untouched for inspection", snapshot_path(dir).string(), e.what()));
  }
  const std::uint64_t snapshot_tasks = task_events(tasks);
  const std::filesystem::path old = old_journal_path(dir);
  const RecordReplay journal = read_record_file(
      old, kJournal,
      [&](const std::string& payload) -> std::string {
        stop_if_asked();
        try {
          BuildCommit commit = decode_commit(payload);
          // Commits the snapshot holds already (an earlier fold wrote it, then stopped): skip them.
          if (has_snapshot && snapshot_holds(commit, snapshot_samples, snapshot_tasks)) return {};
          if (commit.samples < whole.samples) throw std::runtime_error("it goes back in samples");
          fold_tasks(tasks, commit);  // throws, changing nothing, when its task events do not follow
          append_batch(whole.roadmap, std::move(commit.roadmap));
          append_batch(whole.dense, std::move(commit.dense));
          append_all(whole.new_dense_ids, std::move(commit.new_dense_ids));
          whole.samples = commit.samples;
          return {};
        } catch (const RecordWriteStopped&) {
          throw;
        } catch (const std::runtime_error& e) {
          return std::string("unusable commit: ") + e.what();
        }
      },
      fs, RecordKeep::count);
  if (journal.torn_tail) {
    // A journal is whole when it is rotated (a failed append is cut back first): any bad byte in
    // it is damage, not a crash's torn tail.
    throw StoreDamage(fmt::format("{} is damaged at byte {} (commit {}): {}; left untouched for inspection",
                                  old.string(), journal.valid_bytes, journal.records + 1, journal.tail_problem));
  }
  set_tasks(whole, tasks);
  return whole;
}

void RoadmapStore::start_compaction() {
  if (compacting_) return;  // still folding the last journal: a later commit starts the next
  if (compactor_.joinable()) compactor_.join();
  if (!fs_.exists(old_journal_path(dir_))) {
    // journal.log becomes journal.old and a new, empty journal.log follows. A crash between the
    // two leaves no journal.log, which reads as an empty one.
    const std::uint64_t size = journal_->size();
    journal_.reset();
    try {
      fs_.rename(journal_path(dir_), old_journal_path(dir_));
      fsync_directory_of(journal_path(dir_), fs_);
    } catch (...) {
      journal_ = std::make_unique<RecordFileWriter>(journal_path(dir_), kJournal, size, fs_);
      throw;
    }
    journal_ = std::make_unique<RecordFileWriter>(journal_path(dir_), kJournal, 0, fs_);
    journal_commits_ = 0;
    // Before the new journal's first append: head names its bytes, durably, so an older head
    // (whose journal_bytes were journal.old's) can never make a torn first append read as damage.
    try {
      write_store_head(dir_, {recipe_.generation, samples_, journal_->size(), task_events_}, fs_, /*durable=*/true);
    } catch (const std::runtime_error&) {
      try {
        (void)fs_.remove(dir_ / "head");  // no head rather than a stale one: the next commit writes it
      } catch (const std::exception&) {
      }
      throw;  // a disk error, told by name (the commit before is durable; the next one mends head)
    }
  }
  fold_in_background();
}

void RoadmapStore::fold_in_background() {
  stop_compacting_ = false;
  compacting_ = true;
  compactor_ = std::thread([this, dir = dir_] {
    std::string error;
    try {
      const auto keep_going = [this] { return !stop_compacting_.load(); };
      const std::string payload = encode_commit(fold(dir, keep_going, fs_));
      write_record_file_atomically(snapshot_path(dir), kSnapshot, payload, keep_going, fs_);
      // The snapshot holds every commit of journal.old now; a crash before this removal leaves
      // commits that open() skips, and folds again.
      fs_.remove(old_journal_path(dir));
      fsync_directory_of(old_journal_path(dir), fs_);
    } catch (const RecordWriteStopped&) {
      // Stopped (closing, unloading, SIGTERM): journal.old stays, and the next open() folds it.
    } catch (const std::exception& e) {
      error = e.what();
    }
    {
      std::lock_guard lock(compaction_mutex_);
      compaction_error_ = std::move(error);
    }
    compacting_ = false;
  });
}

void RoadmapStore::wait_for_compaction() {
  if (compactor_.joinable()) compactor_.join();
  std::string error;
  {
    std::lock_guard lock(compaction_mutex_);
    error.swap(compaction_error_);
  }
  if (!error.empty()) {
    throw std::runtime_error("compacting " + dir_.string() + " failed: " + error +
                             " (every commit is kept in journal.old and journal.log; the next compaction tries again)");
  }
}

void RoadmapStore::compact() {
  wait_for_compaction();
  start_compaction();
  wait_for_compaction();
}

void RoadmapStore::stop_compaction() {
  stop_compacting_ = true;
  if (compactor_.joinable()) compactor_.join();
}

}  // namespace ispars::service
