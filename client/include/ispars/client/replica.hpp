#pragma once
// A live local copy of a scene's roadmap: a snapshot at version v, then every update batch after
// v, with gaps and duplicates detected; a gap, a rebuilt roadmap or a lost history resyncs it
// from a fresh snapshot.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "ispars/client/client.hpp"

namespace ispars::client {

/// What a replica reports after each change.
struct ReplicaEvent {
  std::uint64_t generation = 0;
  std::uint64_t version = 0;
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::uint64_t samples_done = 0;
  bool resynced = false;  ///< This change was a (re)sync from a snapshot.
};

/// How much a replica queues while its thread is busy (a slow `on_change`, a snapshot in
/// flight), and how long it trusts the batch stream. Past either queue bound the oldest queued
/// batches are dropped, as the daemon's kept history drops its oldest: the gap they leave is
/// detected as any gap is, and the replica resyncs from a fresh snapshot. The newest batch is
/// always kept. The owner's status showing a later version than the replica's for `lag` while no
/// batch arrives (a batch lost for good, and an idle owner writes no other to show the gap), or
/// other POIs at the replica's version (a task that needed no vertex, whose batch it missed),
/// also resyncs it.
struct ReplicaLimits {
  std::size_t batches = 1024;           ///< 1 .. 1,000,000
  std::size_t bytes = 256u << 20;       ///< 64 KiB .. 64 GiB, counted as the batches' array payloads
  std::chrono::milliseconds lag{2000};  ///< 100 ms .. 1 h
};

/// Why a replica took each of its snapshots, counted.
struct ReplicaResyncs {
  std::size_t first = 0;   ///< The first sync, and the first after a drop or unload emptied it.
  std::size_t gap = 0;     ///< A batch showed a gap (lost on the way, or dropped from the queue).
  std::size_t moved = 0;   ///< A batch or status of another roadmap or owner: a rebuild, new POIs, a move.
  std::size_t lag = 0;     ///< The owner's status stayed ahead (or other POIs) for ReplicaLimits::lag.
  std::size_t rejoin = 0;  ///< The client joined the domain again (a new participant).
};

class RoadmapReplica {
 public:
  /// Subscribes to `scene`'s updates through `client` (which must outlive the replica), then
  /// takes the first snapshot. `on_change` runs on the replica's own thread. Throws
  /// std::invalid_argument naming a limit out of its range.
  RoadmapReplica(Client& client, std::string scene, std::function<void(const ReplicaEvent&)> on_change = {},
                 ReplicaLimits limits = {});
  ~RoadmapReplica();
  RoadmapReplica(const RoadmapReplica&) = delete;
  RoadmapReplica& operator=(const RoadmapReplica&) = delete;

  /// A copy of the replica as it is now.
  [[nodiscard]] Roadmap roadmap() const;
  [[nodiscard]] std::uint64_t version() const;
  /// Calls `read(roadmap, generation, samples_done)` with the replica as it is now, under its
  /// lock: what a reader takes of it without copying the whole (keep it short; updates wait).
  void read(const std::function<void(const Roadmap&, std::uint64_t, std::uint64_t)>& read) const;
  [[nodiscard]] std::uint64_t generation() const;
  /// Snapshots taken (1 after the first sync; more after resyncs).
  [[nodiscard]] std::size_t snapshots_taken() const;
  /// Batches applied on top of snapshots.
  [[nodiscard]] std::size_t batches_applied() const;
  /// Batches of other scenes that reached this replica's reader: 0, as it subscribes through a
  /// filter on its scene (wire/scene_filter.hpp).
  [[nodiscard]] std::size_t batches_of_other_scenes() const;
  /// Batches dropped from a full queue (each drop leads to a resync).
  [[nodiscard]] std::size_t batches_dropped() const;
  /// Why each snapshot was taken (their sum is snapshots_taken(), failed attempts not counted).
  [[nodiscard]] ReplicaResyncs resyncs() const;
  /// The scene's root and POIs (from the first snapshot).
  [[nodiscard]] Vec3 root() const;
  [[nodiscard]] std::vector<Vec3> pois() const;
  /// Waits until the replica reaches `version` of `generation` (0: any generation).
  bool wait_for(std::uint64_t generation, std::uint64_t version, std::chrono::milliseconds timeout) const;
  /// Times the owner's status said the roadmap followed was dropped (EMPTY) or its scene unloaded:
  /// each empties the replica (generation 0) until a later build or load brings it back.
  [[nodiscard]] std::size_t retirements() const;
  /// The last error of a sync attempt (empty when none).
  [[nodiscard]] std::string last_error() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::client
