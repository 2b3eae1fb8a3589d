#pragma once
// Continuous viewpoint refinement of a flown tour, after Bircher et al. ("Structural inspection
// path planning via iterative viewpoint resampling", ICRA 2015): a stop need not be a roadmap
// vertex. Each stop is drawn again where it would shorten the tour (inside the prolate spheroid
// with foci at its two neighbours, as Informed RRT* samples): straight toward its neighbours'
// chord, near where it is, and anywhere in the spheroid; it moves to the best draw that is valid,
// joined to both neighbours by valid segments, and sees every target no other stop sees. A stop whose targets all stay
// seen goes when its neighbours can be joined. Then 2-opt over the stops, with checked segments. Repeated until a pass
// gains nothing.
//
// Every change is checked against the scene (point, segments, visibility), so the path stays
// closed, collision-free and seeing every target, and its length never grows.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

struct RefineOptions {
  std::size_t draws = 24;  ///< Candidate positions per stop per pass.
  std::size_t passes = 8;  ///< At most this many passes (fewer when one gains nothing).
  std::uint64_t seed = 1;  ///< The draws' stream: the same input gives the same path.
  /// When set and true, refinement stops after the current stop (the path is still sound).
  const std::atomic<bool>* stop = nullptr;
  /// When > 0, refinement stops as `stop` does once this many seconds have passed.
  double budget_seconds = 0.0;
};

struct RefineResult {
  std::size_t moved = 0;     ///< Stops moved to a better position.
  std::size_t dropped = 0;   ///< Stops removed.
  std::size_t reversed = 0;  ///< 2-opt moves.
  std::size_t passes = 0;
  std::size_t segments_checked = 0;
  std::size_t visibility_queries = 0;
  bool stopped = false;  ///< `stop` or the budget ended it.
};

/// The length of a path of straight segments.
[[nodiscard]] double path_length(std::span<const Vec3> stops);

/// Refines the closed path `stops` (front == back: the root, which never moves) in place,
/// keeping every one of `targets` (ascending POI ids of `scene`) seen from some stop: it must be
/// so on entry. Throws std::invalid_argument when the path is not closed or a target is not seen.
RefineResult refine_viewpoints(const Scene& scene, std::span<const PoiId> targets, std::vector<Vec3>& stops,
                               const RefineOptions& options = {});

}  // namespace ispars::planning
