// The checks that find a store's damage without opening it: its first bytes and length
// (store_quick_problem, for every listing), and every record read whole (store_scrub_problem, for
// the background check of stored copies); and the damage rules recovery shares with them.

#include <fmt/format.h>

#include <algorithm>
#include <fstream>

#include "ispars/service/roadmap_store.hpp"
#include "roadmap_store_damage.hpp"
#include "roadmap_store_files.hpp"

namespace ispars::service {
namespace store_files {

std::string damage_text(const std::filesystem::path& path, const RecordReplay& replay, const FileSystem& fs) {
  return fmt::format(
      "{} is damaged at byte {} (commit {}): {}; the {} bytes from there on are left untouched for "
      "inspection (drop the scene's roadmap, or build with replace, to discard them)",
      path.string(), replay.valid_bytes, replay.records + 1, replay.tail_problem,
      fs.file_size(path).value_or(replay.valid_bytes) - replay.valid_bytes);
}

std::optional<RecordReplay> journal_damage(const std::filesystem::path& dir, const RecordReplay& journal,
                                           const FileSystem& fs) {
  const std::optional<StoreHead> head = read_store_head(dir, fs);
  const std::uint64_t file_bytes = fs.file_size(journal_path(dir)).value_or(0);
  if (head && journal.torn_tail && journal.valid_bytes < head->journal_bytes && head->journal_bytes <= file_bytes) {
    RecordReplay named = journal;
    named.tail_problem += fmt::format(" in an acknowledged commit (head: durable to byte {})", head->journal_bytes);
    return named;
  }
  if (journal.damaged) return journal;
  return std::nullopt;
}

std::optional<std::string> snapshot_damage(const std::filesystem::path& dir, const RecordReplay& snapshot) {
  if (snapshot.records == 1 && !snapshot.torn_tail) return std::nullopt;
  return fmt::format("{} is damaged at byte {}: {}; left untouched for inspection", snapshot_path(dir).string(),
                     snapshot.valid_bytes,
                     snapshot.tail_problem.empty() ? "not exactly one record" : snapshot.tail_problem);
}

}  // namespace store_files

using namespace store_files;

namespace {

// Whether `path`, when it exists and is not empty, starts with one of `format`'s magics (or, with
// `torn_header`, is a prefix of the current one: a crash while a journal's header was written; a
// snapshot is written whole and renamed into place).
bool starts_as(const std::filesystem::path& path, const RecordFormat& format, bool torn_header) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return true;  // absent: recovery decides
  std::string prefix(format.magic().size(), '\0');
  in.read(prefix.data(), static_cast<std::streamsize>(prefix.size()));
  prefix.resize(static_cast<std::size_t>(in.gcount()));
  if (prefix.empty() || (torn_header && format.magic().substr(0, prefix.size()) == prefix)) return true;
  return std::any_of(format.versions.begin(), format.versions.end(),
                     [&](const RecordMagic& m) { return prefix == m.magic; });
}

}  // namespace

std::string store_quick_problem(const std::filesystem::path& dir) {
  for (const auto& [path, format] : {std::pair{snapshot_path(dir), &kSnapshot}, std::pair{journal_path(dir), &kJournal},
                                     std::pair{old_journal_path(dir), &kJournal}}) {
    if (!starts_as(path, *format, format == &kJournal)) {
      return fmt::format("{} does not start as a {} file (damaged at byte 0)", path.string(), format->magic());
    }
  }
  std::error_code ec;
  const auto size = std::filesystem::file_size(journal_path(dir), ec);
  const auto head = read_store_head(dir);
  if (head && head->journal_bytes > 0 && (ec || size < head->journal_bytes)) {
    return fmt::format("{} has {} bytes, and its head says {} were durable", journal_path(dir).string(), ec ? 0 : size,
                       head->journal_bytes);
  }
  return {};
}

std::string store_scrub_problem(const std::filesystem::path& dir, const FileSystem& fs) {
  const auto whole = [](const std::string&) { return std::string(); };  // framing and checksums only
  try {
    if (fs.exists(snapshot_path(dir))) {
      const RecordReplay snapshot = read_record_file(snapshot_path(dir), kSnapshot, whole, fs, RecordKeep::count);
      if (auto problem = snapshot_damage(dir, snapshot)) return *problem;
    }
    if (fs.exists(old_journal_path(dir))) {
      const RecordReplay old = read_record_file(old_journal_path(dir), kJournal, whole, fs, RecordKeep::count);
      if (old.torn_tail) return damage_text(old_journal_path(dir), old, fs);
    }
    const RecordReplay journal = read_record_file(journal_path(dir), kJournal, whole, fs, RecordKeep::count);
    if (const auto damaged = journal_damage(dir, journal, fs)) return damage_text(journal_path(dir), *damaged, fs);
  } catch (const RecordMagicMismatch& e) {
    return fmt::format("{} (damaged at byte 0)", e.what());
  }
  return {};
}

}  // namespace ispars::service
