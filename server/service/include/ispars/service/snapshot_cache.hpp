#pragma once
// Snapshots of a roadmap in bounded chunks: each version encoded once, its encoding kept for the
// chunks that follow (and other clients' snapshots of the same version), a few at a time. An
// encoding leases its worst case from the memory budget while it is made, then its size while it
// is kept; the budget drops every kept encoding when a build, tour or snapshot needs the room.

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ispars/service/memory_budget.hpp"
#include "ispars/service/roadmap_session.hpp"

namespace ispars::service {

/// One slice of a roadmap encoded at one version, for transfer in bounded chunks.
struct SnapshotSlice {
  std::uint64_t generation = 0;
  std::uint64_t version = 0;
  std::uint32_t chunk_index = 0;
  std::uint32_t chunk_count = 0;
  std::size_t poi_count = 0;                   ///< The roadmap's POIs (the scene's, then its tasks').
  std::shared_ptr<const std::string> encoded;  ///< The whole encoding; this slice is [begin, end).
  std::size_t begin = 0;
  std::size_t end = 0;
};
inline constexpr std::size_t kSnapshotChunkBytes = 1024 * 1024;

/// The service's snapshot encodings, the few most recent kept; safe from many threads.
class SnapshotCache {
 public:
  /// Leases from `budget`; an encoding in progress stops at its next slice once `go_on` is false
  /// (the daemon is stopping).
  SnapshotCache(std::shared_ptr<MemoryBudget> budget, std::function<bool()> go_on);

  /// Chunk `chunk_index` of `session`'s roadmap (scene `scene`) at `version` of `generation` with
  /// `poi_count` POIs (version 0: the latest; 0 POIs: any). Throws InputError when that version is
  /// no longer published, the chunk is past the last, the budget has no room, or the encoding
  /// was stopped.
  [[nodiscard]] SnapshotSlice slice(const RoadmapSession& session, const std::string& scene, std::uint64_t version,
                                    std::uint64_t generation, std::uint32_t chunk_index, std::size_t poi_count);
  /// Gives every kept encoding's lease back (the budget's reclaimer).
  void drop_all();
  /// Encodings kept now.
  [[nodiscard]] std::size_t kept() const;

 private:
  struct Encoded {
    std::string scene;
    std::uint64_t generation = 0;
    std::uint64_t version = 0;
    std::size_t poi_count = 0;
    std::shared_ptr<const std::string> bytes;  // holds its lease of the budget
    std::chrono::steady_clock::time_point used;
  };
  /// The kept encoding of that version (its POI count into `poi_count`), or null; drops the expired.
  std::shared_ptr<const std::string> find(const std::string& scene, std::uint64_t generation, std::uint64_t version,
                                          std::size_t& poi_count);
  std::shared_ptr<const std::string> encode(const RoadmapSession& session, const std::string& scene,
                                            std::uint64_t& version, std::uint64_t& generation, std::size_t& poi_count);

  std::shared_ptr<MemoryBudget> budget_;
  std::function<bool()> go_on_;
  mutable std::mutex mutex_;
  std::vector<Encoded> kept_;  // the few most recent, oldest first
};

}  // namespace ispars::service
