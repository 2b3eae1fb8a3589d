#pragma once
// The independent check of a flown tour: everything it claims, derived again from the scene
// alone. No roadmap, no visibility a builder stored, no solver state: the stops' positions, the
// scene's collision checker and its visibility rays. A tour that smoothing or refinement broke
// (a stop moved out of view of its POI, a segment through the structure) fails it, named.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/poi_id.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// What check_flown_tour found; valid() when `problem` is empty.
struct FlownTourCheck {
  double recomputed_cost = 0.0;  ///< The sum of the segments' lengths.
  std::size_t missing_targets = 0;
  std::vector<std::vector<PoiId>> sees;  ///< Per stop (the closing one too): the targets it sees, ascending.
  std::string problem;                   ///< The first failure, in words.
  [[nodiscard]] bool valid() const { return problem.empty(); }
};

/// Checks the closed path `stops` against `scene`: it starts and ends at `root`, every stop is a
/// valid configuration inside the sampling box, every segment is collision-free, every one of
/// `targets` (ascending) is seen from some stop (rays cast now), and `stated_cost` is the sum of
/// the segments' lengths (to 1e-9 relative).
[[nodiscard]] FlownTourCheck check_flown_tour(const Scene& scene, const Vec3& root, std::span<const PoiId> targets,
                                              std::span<const Vec3> stops, double stated_cost);

}  // namespace ispars::planning
