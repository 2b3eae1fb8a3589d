#pragma once
// Validity of robot configurations and of straight motions for a sphere robot.

#include <memory>

#include "ispars/planning/geometry/check_counters.hpp"
#include "ispars/planning/geometry/embree_scene.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// Decides whether a sphere of radius r centred at q is valid (q inside the sampling box and
/// every triangle farther than r) and whether the straight motion between two centres is valid
/// (the capsule it sweeps touches no triangle). Both are exact: the BVH only culls, the final
/// word is an exact double-precision distance. All queries are const and thread-safe.
class CollisionChecker {
 public:
  CollisionChecker(std::shared_ptr<const EmbreeScene> scene, Aabb bounds, double robot_radius);

  /// True when q is inside the bounds and its distance to every triangle exceeds the radius.
  [[nodiscard]] bool point_valid(const Vec3& q) const;
  /// True when both ends are inside the bounds and the swept sphere along [a, b] keeps a
  /// distance above the radius from every triangle. Exact: no sampling along the segment.
  [[nodiscard]] bool segment_valid(const Vec3& a, const Vec3& b) const;
  /// Exact distance from q to the nearest triangle (the robot's clearance is this minus r).
  [[nodiscard]] double distance_to_surface(const Vec3& q) const;

  [[nodiscard]] double robot_radius() const { return radius_; }
  [[nodiscard]] const Aabb& bounds() const { return bounds_; }
  [[nodiscard]] CheckCounts counts() const { return counters_.snapshot(); }

 private:
  bool capsule_free(const Vec3& a, const Vec3& b) const;

  std::shared_ptr<const EmbreeScene> scene_;
  Aabb bounds_;
  double radius_;
  CheckCounters counters_;
};

}  // namespace ispars::planning
