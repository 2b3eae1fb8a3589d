#pragma once
// Roadmap batches: everything a roadmap gained between two versions, as the service's journal,
// snapshots and update stream carry it. A batch's encoding holds the version range it covers and
// the vertices (position, visible POIs) and edges (u, v, cost) it added, in change-log order;
// a replica applies a batch only when it continues it exactly, and whole or not at all.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// One committed batch: everything a roadmap gained between two versions.
struct RoadmapBatch {
  std::uint64_t from_version = 0;  ///< The roadmap's version before the batch.
  std::uint64_t to_version = 0;    ///< ... and after it.
  std::vector<RoadmapChange> changes;
  std::vector<Vec3> positions;              ///< For each vertex change, in order.
  std::vector<std::vector<PoiId>> visible;  ///< For each vertex change, in order.
  std::vector<RoadmapEdge> edges;           ///< For each edge change, in order.
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

/// Serialises a batch to its payload encoding, and back (throws std::runtime_error on a
/// payload that does not parse exactly).
[[nodiscard]] std::string encode_batch(const RoadmapBatch& batch);
/// encode_batch's bytes appended to `out`, which grows once, by exactly encoded_batch_size().
void append_encoded_batch(std::string& out, const RoadmapBatch& batch);
[[nodiscard]] std::size_t encoded_batch_size(const RoadmapBatch& batch);
/// encode_batch(batch_range(roadmap, 0, to)), gathered a slice of versions at a time and asking
/// `keep_going` between slices (a large roadmap's encoding takes seconds): nothing when it says
/// stop, and the bytes are dropped.
[[nodiscard]] std::optional<std::string> encode_prefix(const Roadmap& roadmap, std::uint64_t to,
                                                       const std::function<bool()>& keep_going);
[[nodiscard]] RoadmapBatch decode_batch(std::string_view payload);

}  // namespace ispars
