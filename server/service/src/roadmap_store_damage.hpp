#pragma once
// How a roadmap store's damage is told from a crash's tear, and said: shared by its recovery
// (roadmap_store.cpp), which refuses a damaged store, and the checks that find damage without
// opening it (store_quick_problem, store_scrub_problem in roadmap_store_checks.cpp).

#include <filesystem>
#include <optional>
#include <string>

#include "ispars/roadmap/file_system.hpp"
#include "ispars/roadmap/record_file.hpp"

namespace ispars::service::store_files {

/// What a record file's damage is, in words: where, in which record, and that it is left as it is.
[[nodiscard]] std::string damage_text(const std::filesystem::path& path, const RecordReplay& replay,
                                      const FileSystem& fs);

/// Whether journal.log as read (`journal`) is damaged, not torn by a crash: a record refused, or a
/// bad record inside the bytes the store's head says were durable (and the file still holds):
/// acknowledged. (A head older than the journal, as after a compaction's rotation, names more
/// bytes than the new file holds, and says nothing.) The journal's replay with its problem said,
/// or nothing.
[[nodiscard]] std::optional<RecordReplay> journal_damage(const std::filesystem::path& dir, const RecordReplay& journal,
                                                         const FileSystem& fs);

/// A snapshot holds exactly one whole record; else what is wrong, in words.
[[nodiscard]] std::optional<std::string> snapshot_damage(const std::filesystem::path& dir,
                                                         const RecordReplay& snapshot);

}  // namespace ispars::service::store_files
