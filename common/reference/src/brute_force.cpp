#include "ispars/reference/brute_force.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ispars::reference {

BruteForceGeometry::BruteForceGeometry(std::vector<planning::Triangle> triangles, Aabb bounds, double robot_radius,
                                       std::vector<Vec3> pois, double sensor_range)
    : triangles_(std::move(triangles)),
      bounds_(bounds),
      radius_(robot_radius),
      pois_(std::move(pois)),
      range_(sensor_range) {}

double BruteForceGeometry::distance_to_surface(const Vec3& q) const {
  double best = INFINITY;
  for (const auto& t : triangles_) best = std::min(best, planning::point_triangle_distance_squared(q, t));
  return std::sqrt(best);
}

double BruteForceGeometry::segment_distance_to_surface(const Vec3& a, const Vec3& b) const {
  double best = INFINITY;
  for (const auto& t : triangles_) {
    best = std::min(best, planning::segment_triangle_distance_squared(a, b, t));
  }
  return std::sqrt(best);
}

bool BruteForceGeometry::point_valid(const Vec3& q) const {
  if (!bounds_.contains(q)) return false;
  const double r2 = radius_ * radius_;
  for (const auto& t : triangles_) {
    if (planning::point_triangle_distance_squared(q, t) <= r2) return false;
  }
  return true;
}

bool BruteForceGeometry::segment_valid(const Vec3& a, const Vec3& b) const {
  if (!bounds_.contains(a) || !bounds_.contains(b)) return false;
  const double r2 = radius_ * radius_;
  for (const auto& t : triangles_) {
    if (planning::segment_triangle_distance_squared(a, b, t) <= r2) return false;
  }
  return true;
}

ReferenceSight BruteForceGeometry::line_of_sight(const Vec3& q, PoiId id, double tolerance) const {
  const Vec3 d = pois_[id] - q;
  const double length = d.norm();
  const double s_end = length > planning::kPoiStandoff ? 1.0 - planning::kPoiStandoff / length : 0.0;
  ReferenceSight sight;
  for (const auto& t : triangles_) {
    const auto crossing = planning::ray_plane_crossing(q, d, t);
    if (!crossing) continue;
    const bool inside_span = crossing->s >= 0.0 && crossing->s <= s_end;
    const bool hit = inside_span && crossing->margin >= 0.0;
    if (hit) sight.visible = false;
    const bool near_span = crossing->s >= -tolerance && crossing->s <= s_end + tolerance;
    const bool near_edge = std::abs(crossing->margin) <= tolerance;
    const bool near_end = std::abs(crossing->s - s_end) <= tolerance || std::abs(crossing->s) <= tolerance;
    if ((near_span && near_edge) || (crossing->margin >= -tolerance && near_end)) {
      sight.ambiguous = true;
    }
  }
  return sight;
}

std::vector<PoiId> BruteForceGeometry::visible_pois(const Vec3& q, std::vector<PoiId>* ambiguous) const {
  std::vector<PoiId> out;
  if (ambiguous != nullptr) ambiguous->clear();
  const double range2 = range_ * range_;
  for (std::size_t i = 0; i < pois_.size(); ++i) {
    if ((pois_[i] - q).squaredNorm() > range2) continue;
    const auto id = static_cast<PoiId>(i);
    const ReferenceSight sight = line_of_sight(q, id);
    if (sight.visible) out.push_back(id);
    if (sight.ambiguous && ambiguous != nullptr) ambiguous->push_back(id);
  }
  return out;
}

}  // namespace ispars::reference
