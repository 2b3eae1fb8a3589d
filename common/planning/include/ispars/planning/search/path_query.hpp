#pragma once
// Point-to-point queries on a sparse roadmap: join the start and goal to it within Delta, then
// search it.

#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// A collision-free path from start to goal.
struct RoadmapPath {
  std::vector<Vec3> waypoints;     ///< start, the roadmap vertices in order, goal.
  std::vector<VertexId> vertices;  ///< The roadmap vertices used.
  double length = 0.0;             ///< Sum of the segment lengths.
};

/// The shortest path from `start` to `goal` through `roadmap`, entering and leaving it by free
/// segments to vertices within `join_radius` (Delta). The straight segment is taken instead when
/// the points are within `join_radius`, it is free and no route is shorter (even when the joins
/// lie in different components; both points still need a join). Throws InputError
/// (file "path", field "from" or "to") when a point is non-finite, outside the scene's bounds, in
/// collision, or has no free segment to a vertex within the radius, and (field "to") when the two
/// joins lie in different components.
[[nodiscard]] RoadmapPath plan_path(const Scene& scene, const Roadmap& roadmap, const Vec3& start, const Vec3& goal,
                                    double join_radius);

}  // namespace ispars::planning
