#pragma once
// A scene's stored roadmap as its session takes it over at load: the store opened for writing,
// the roadmap to publish with its tasks' POIs seen, what a builder resumes from, or why the
// store is refused (its files then stay as they are).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/service/build_request.hpp"
#include "ispars/service/inspection_task.hpp"
#include "ispars/service/published_roadmap.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/session_record.hpp"

namespace ispars::service {

/// What recover_session() found in a scene's store directory. With nothing stored and nothing
/// refused, the directory held no store.
struct RecoveredSession {
  /// Why the stored roadmap is not served (damage, or a roadmap of another version of the scene
  /// or of the builder); empty when it is. A refused store is closed, its files untouched.
  std::string refused;
  /// No store: the generation of a drop made there before, which the empty roadmap keeps.
  std::optional<std::uint64_t> dropped_generation;
  std::unique_ptr<RoadmapStore> store;  ///< Open for writing (compacting every limits.compact_every).
  std::optional<StoredRoadmap> stored;  ///< The stored roadmap, as the session serves it.
  /// The stored roadmaps, for a method whose builder cannot resume from the published roadmap.
  std::optional<planning::BuiltRoadmaps> resume_from;
  std::string note;            ///< What was recovered, for the log.
  std::string torn_tail_note;  ///< What a torn journal tail cut off and where it was kept; empty if none.
};

/// The roadmap `recovery` holds (of `scene` as loaded), as a session serves it: `scene` with the
/// stored tasks' POIs, and the roadmaps made to see those of them their vertices see (the store
/// has no scene: a vertex built before a task does not know its POIs), on `threads` threads. The
/// roadmaps go to `resume_from` for a method whose builder cannot resume from the published
/// roadmap; the published copy takes them over otherwise.
[[nodiscard]] StoredRoadmap serve_recovery(const planning::Scene& scene, StoreRecovery& recovery, unsigned threads,
                                           std::optional<planning::BuiltRoadmaps>& resume_from);

/// Opens the store of scene `name` (`scene` as loaded, its fingerprint `fingerprint`) in
/// `store_dir` on `fs`, and recovers its roadmap. Throws std::runtime_error when the store is
/// another scene's.
[[nodiscard]] RecoveredSession recover_session(const std::string& name, const planning::Scene& scene,
                                               const std::string& fingerprint, const std::filesystem::path& store_dir,
                                               const SessionLimits& limits, FileSystem& fs);

}  // namespace ispars::service
