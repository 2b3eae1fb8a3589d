#pragma once
// Reference geometry: every query answered by scanning every triangle with the exact primitives.
// Slow by design; the tests and `ispars-lab bench geometry` hold the fast paths against it.

#include <memory>
#include <vector>

#include "ispars/planning/geometry/distance.hpp"
#include "ispars/planning/geometry/visibility.hpp"

namespace ispars::reference {

/// A line of sight judged by the reference, with a flag for the tolerance band: a ray that
/// passes within `tolerance` (barycentric, or in ray parameter) of some triangle's boundary or
/// of its own end, where single-precision ray tracing may legitimately decide either way.
struct ReferenceSight {
  bool visible = true;
  bool ambiguous = false;
};

/// Brute-force collision, clearance and visibility over all triangles, in double precision.
class BruteForceGeometry {
 public:
  BruteForceGeometry(std::vector<planning::Triangle> triangles, Aabb bounds, double robot_radius,
                     std::vector<Vec3> pois, double sensor_range);

  [[nodiscard]] bool point_valid(const Vec3& q) const;
  [[nodiscard]] bool segment_valid(const Vec3& a, const Vec3& b) const;
  [[nodiscard]] double distance_to_surface(const Vec3& q) const;
  /// Exact distance from the segment [a, b] to the nearest triangle.
  [[nodiscard]] double segment_distance_to_surface(const Vec3& a, const Vec3& b) const;
  [[nodiscard]] ReferenceSight line_of_sight(const Vec3& q, PoiId id, double tolerance = 1e-5) const;
  /// chi(q) by scanning every POI and casting against every triangle; `ambiguous` (if given)
  /// receives the ids whose sight line is in the tolerance band.
  [[nodiscard]] std::vector<PoiId> visible_pois(const Vec3& q, std::vector<PoiId>* ambiguous = nullptr) const;

  [[nodiscard]] const std::vector<planning::Triangle>& triangles() const { return triangles_; }

 private:
  std::vector<planning::Triangle> triangles_;
  Aabb bounds_;
  double radius_;
  std::vector<Vec3> pois_;
  double range_;
};

}  // namespace ispars::reference
