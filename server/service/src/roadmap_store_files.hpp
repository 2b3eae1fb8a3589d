#pragma once
// The files of a roadmap store (roadmap_store.hpp) and their record formats: shared by the store
// and its compaction.

#include <filesystem>

#include "ispars/roadmap/record_file.hpp"

namespace ispars::store_files {

/// Format 02 allows records of any size; 01 files (32-bit lengths) are still read and appended to.
inline const RecordFormat kJournal{"ISPJRN02", "ISPJRN01"};
inline const RecordFormat kSnapshot{"ISPSNP02", "ISPSNP01"};

inline std::filesystem::path journal_path(const std::filesystem::path& dir) { return dir / "journal.log"; }
/// The journal a running (or interrupted) compaction folds into the snapshot.
inline std::filesystem::path old_journal_path(const std::filesystem::path& dir) { return dir / "journal.old"; }
inline std::filesystem::path snapshot_path(const std::filesystem::path& dir) { return dir / "snapshot.bin"; }
inline std::filesystem::path recipe_path(const std::filesystem::path& dir) { return dir / "recipe.json"; }

}  // namespace ispars::store_files
