#pragma once
// The files of a roadmap store (roadmap_store.hpp) and their record formats: shared by the store
// and its compaction.

#include <filesystem>

#include "ispars/roadmap/record_file.hpp"

namespace ispars::service::store_files {

/// Format 03 checks each record header on its own, so a damaged length is told from a torn tail;
/// 02 (records of any size) and 01 (32-bit lengths) files are still read and appended to.
inline const RecordFormat kJournal{
    {"ISPJRN03", RecordLayout::checked}, {"ISPJRN02", RecordLayout::escaped}, {"ISPJRN01", RecordLayout::plain}};
inline const RecordFormat kSnapshot{
    {"ISPSNP03", RecordLayout::checked}, {"ISPSNP02", RecordLayout::escaped}, {"ISPSNP01", RecordLayout::plain}};

inline std::filesystem::path journal_path(const std::filesystem::path& dir) { return dir / "journal.log"; }
/// The journal a running (or interrupted) compaction folds into the snapshot.
inline std::filesystem::path old_journal_path(const std::filesystem::path& dir) { return dir / "journal.old"; }
inline std::filesystem::path snapshot_path(const std::filesystem::path& dir) { return dir / "snapshot.bin"; }
inline std::filesystem::path recipe_path(const std::filesystem::path& dir) { return dir / "recipe.json"; }

}  // namespace ispars::service::store_files
