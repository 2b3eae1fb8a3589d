#pragma once
// A scene's drop, remembered after its store is gone: DATA_DIR/.drops/NAME holds the generation
// of the empty roadmap a DROP left. The fleet weighs it like any copy (generation G, no samples),
// so an older copy on another daemon never serves the scene again while the daemon that dropped
// it is live, loaded or not, restarted or not (docs/fleet.md). A store of the scene, when there
// is one, is the truth and the mark is not read.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "ispars/roadmap/file_system.hpp"

namespace ispars::service {

/// Records that the scene whose store is (or was) `store_dir` was dropped at `generation`,
/// durably (written atomically and fsync'ed, with its directory), before the store goes.
/// Throws std::runtime_error naming the file when it cannot be written.
void mark_dropped(const std::filesystem::path& store_dir, std::uint64_t generation, FileSystem& fs = disk());

/// The generation the scene of `store_dir` was last dropped at; nothing when never dropped here
/// (or the mark is unreadable, which is logged by the caller's listing, not thrown).
[[nodiscard]] std::optional<std::uint64_t> dropped_generation(const std::filesystem::path& store_dir,
                                                              const FileSystem& fs = disk());

/// A dropped scene of `data_dir` and the generation of its drop.
struct DropMark {
  std::string scene;
  std::uint64_t generation = 0;
};

/// Every readable drop mark in `data_dir`, sorted by scene.
[[nodiscard]] std::vector<DropMark> list_drop_marks(const std::filesystem::path& data_dir,
                                                    const FileSystem& fs = disk());

}  // namespace ispars::service
