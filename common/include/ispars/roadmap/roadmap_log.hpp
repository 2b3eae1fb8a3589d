#pragma once
// A crash-safe, append-only log of roadmap batches: the persistence the service replays.
//
// File: an 8-byte magic, then records. A record is [u32 payload length][u32 CRC-32 of the
// payload][payload], little-endian. A payload is one batch: the version range it covers and the
// vertices (position, visible POIs) and edges (u, v, cost) it added, in change-log order.
// Appends are fsync'ed. A reader replays every whole record and stops at the first torn or
// corrupt one: after a crash at any moment, the log recovers the last committed batch, and a
// torn tail is detected and dropped, never half-applied.

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// One committed batch: everything a roadmap gained between two versions.
struct RoadmapBatch {
  std::uint64_t from_version = 0;  ///< The roadmap's version before the batch.
  std::uint64_t to_version = 0;    ///< ... and after it.
  std::vector<RoadmapChange> changes;
  std::vector<Vec3> positions;                  ///< For each vertex change, in order.
  std::vector<std::vector<PoiId>> visible;      ///< For each vertex change, in order.
  std::vector<RoadmapEdge> edges;               ///< For each edge change, in order.
};

/// The batch of every change of `roadmap` after `version`.
[[nodiscard]] RoadmapBatch batch_since(const Roadmap& roadmap, std::uint64_t version);
/// The batch of the changes of `roadmap` after `from` up to and including version `to`
/// (clamped to the roadmap's version).
[[nodiscard]] RoadmapBatch batch_range(const Roadmap& roadmap, std::uint64_t from, std::uint64_t to);

/// A 64-bit digest (FNV-1a) of a roadmap's whole change log: equal roadmaps, built or replicated
/// in the same order, have equal digests.
[[nodiscard]] std::uint64_t roadmap_digest(const Roadmap& roadmap);

/// Applies a batch to a replica whose version is batch.from_version. Throws std::runtime_error,
/// leaving the replica untouched, when the batch does not continue it (a gap, a duplicate, an id
/// out of order) or is malformed (a POI id out of range, a non-finite position, a wrong cost).
void apply_batch(Roadmap& replica, const RoadmapBatch& batch);
/// apply_batch's check alone: throws std::runtime_error naming what does not fit; changes nothing.
void check_batch(const Roadmap& replica, const RoadmapBatch& batch);
/// apply_batch without its check, for a batch check_batch accepted against this very replica (a
/// store checks every part of a commit before it applies any).
void apply_checked_batch(Roadmap& replica, const RoadmapBatch& batch);

/// What reading a log found.
struct LogReplay {
  std::vector<RoadmapBatch> batches;  ///< Every whole, valid record, in order.
  std::uint64_t valid_bytes = 0;      ///< Length of the valid prefix of the file.
  bool torn_tail = false;             ///< Bytes after the valid prefix were dropped.
  std::string tail_problem;           ///< What was wrong with them.
};

/// Reads a log file (a missing file is an empty log). Throws std::runtime_error when the file
/// exists but is not a roadmap log (bad magic).
[[nodiscard]] LogReplay read_roadmap_log(const std::filesystem::path& path);

/// Appends batches to a log, durably.
class RoadmapLogWriter {
 public:
  /// Opens (creating it when missing) the log at `path` for appending. A torn tail left by a
  /// crash is cut off first, so new records never follow garbage.
  explicit RoadmapLogWriter(const std::filesystem::path& path);
  ~RoadmapLogWriter();
  RoadmapLogWriter(const RoadmapLogWriter&) = delete;
  RoadmapLogWriter& operator=(const RoadmapLogWriter&) = delete;

  /// Appends one record and fsyncs; when this returns, the batch survives a crash. Throws
  /// std::invalid_argument when the batch does not continue the log's last version.
  void append(const RoadmapBatch& batch);
  /// The version the log ends at (0 for an empty log).
  [[nodiscard]] std::uint64_t version() const { return version_; }
  /// What opening found (the replayed batches are not kept here).
  [[nodiscard]] bool recovered_torn_tail() const { return torn_tail_; }

 private:
  std::unique_ptr<RecordFileWriter> file_;
  bool torn_tail_ = false;
  bool empty_ = true;
  std::uint64_t version_ = 0;
};

/// Serialises a batch to the record payload format, and back (throws std::runtime_error on a
/// payload that does not parse exactly).
[[nodiscard]] std::string encode_batch(const RoadmapBatch& batch);
/// encode_batch's bytes appended to `out`, which grows once, by exactly encoded_batch_size().
void append_encoded_batch(std::string& out, const RoadmapBatch& batch);
[[nodiscard]] std::size_t encoded_batch_size(const RoadmapBatch& batch);
[[nodiscard]] RoadmapBatch decode_batch(std::string_view payload);

}  // namespace ispars
