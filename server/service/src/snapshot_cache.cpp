#include "ispars/service/snapshot_cache.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/build_cost.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "request_input.hpp"

namespace ispars::service {
namespace {

constexpr std::size_t kSnapshotsKept = 4;
// A kept encoding unused this long is dropped (its lease given back) at the next snapshot; any
// is dropped at once when a build, tour or snapshot needs its memory (the budget's reclaimer).
constexpr std::chrono::seconds kSnapshotKeptFor{60};
// A snapshot's encoding at its worst: the batch copied out of the roadmap and its encoding, a
// compaction fold's work over the same vertices and edges (build_cost.hpp).
double snapshot_cost(const Roadmap& roadmap) {
  return static_cast<double>(roadmap.vertex_count()) * planning::kFoldBytesPerVertex +
         static_cast<double>(roadmap.edge_count()) * planning::kFoldBytesPerEdge;
}

}  // namespace

SnapshotCache::SnapshotCache(std::shared_ptr<MemoryBudget> budget, std::function<bool()> go_on)
    : budget_(std::move(budget)), go_on_(std::move(go_on)) {}

void SnapshotCache::drop_all() {
  std::vector<Encoded> dropped;
  {
    std::lock_guard lock(mutex_);
    dropped.swap(kept_);
  }
  if (!dropped.empty()) spdlog::info("dropped {} kept snapshot encodings: their memory is needed", dropped.size());
}

std::size_t SnapshotCache::kept() const {
  std::lock_guard lock(mutex_);
  return kept_.size();
}

std::shared_ptr<const std::string> SnapshotCache::find(const std::string& scene, std::uint64_t generation,
                                                       std::uint64_t version, std::size_t& poi_count) {
  std::shared_ptr<const std::string> bytes;
  std::vector<Encoded> expired;  // released outside the lock
  std::lock_guard lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  for (auto it = kept_.begin(); it != kept_.end();) {
    if (now - it->used > kSnapshotKeptFor) {
      expired.push_back(std::move(*it));
      it = kept_.erase(it);
      continue;
    }
    if (version != 0 && it->scene == scene && it->generation == generation && it->version == version &&
        (poi_count == 0 || it->poi_count == poi_count)) {
      bytes = it->bytes;
      poi_count = it->poi_count;
      it->used = now;
    }
    ++it;
  }
  return bytes;
}

std::shared_ptr<const std::string> SnapshotCache::encode(const RoadmapSession& session, const std::string& scene,
                                                         std::uint64_t& version, std::uint64_t& generation,
                                                         std::size_t& poi_count) {
  const PublishedRoadmap published = session.published();
  if (version == 0) {
    generation = published.generation;
    version = published.roadmap->version();
    poi_count = published.roadmap->poi_count();
  } else if (published.generation != generation || published.roadmap->version() < version ||
             (poi_count != 0 && published.roadmap->poi_count() != poi_count)) {
    throw params::InputError(
        kRequest, "snapshot_version",
        fmt::format("version {} of roadmap generation {} is no longer available; start the snapshot again", version,
                    generation));
  }
  // The encoding's worst case is leased before it is made, then only its size while it is kept.
  const auto lease = budget_->lease(snapshot_cost(*published.roadmap), fmt::format("a snapshot of scene '{}'", scene));
  // Stoppable between slices: a daemon that stops does not wait out a large roadmap's encoding.
  std::optional<std::string> made = encode_prefix(*published.roadmap, version, go_on_);
  if (!made) {
    throw params::InputError(kRequest, "scene",
                             fmt::format("the snapshot of scene '{}' was stopped: the daemon is stopping", scene));
  }
  auto encoded = std::make_unique<const std::string>(std::move(*made));
  lease->shrink_to(static_cast<double>(encoded->size()));
  std::shared_ptr<const std::string> bytes(encoded.release(), [lease](const std::string* p) { delete p; });
  std::lock_guard lock(mutex_);
  poi_count = published.roadmap->poi_count();
  kept_.push_back({scene, generation, version, poi_count, bytes, std::chrono::steady_clock::now()});
  if (kept_.size() > kSnapshotsKept) kept_.erase(kept_.begin());
  return bytes;
}

SnapshotSlice SnapshotCache::slice(const RoadmapSession& session, const std::string& scene, std::uint64_t version,
                                   std::uint64_t generation, std::uint32_t chunk_index, std::size_t poi_count) {
  std::shared_ptr<const std::string> bytes = find(scene, generation, version, poi_count);
  if (!bytes) bytes = encode(session, scene, version, generation, poi_count);
  const std::size_t count = std::max<std::size_t>(1, (bytes->size() + kSnapshotChunkBytes - 1) / kSnapshotChunkBytes);
  if (chunk_index >= count) {
    throw params::InputError(kRequest, "chunk_index",
                             fmt::format("{} is past the last chunk ({})", chunk_index, count - 1));
  }
  SnapshotSlice slice;
  slice.generation = generation;
  slice.version = version;
  slice.chunk_index = chunk_index;
  slice.chunk_count = static_cast<std::uint32_t>(count);
  slice.poi_count = poi_count;
  slice.begin = std::size_t{chunk_index} * kSnapshotChunkBytes;
  slice.end = std::min(bytes->size(), slice.begin + kSnapshotChunkBytes);
  slice.encoded = std::move(bytes);
  return slice;
}

}  // namespace ispars::service
