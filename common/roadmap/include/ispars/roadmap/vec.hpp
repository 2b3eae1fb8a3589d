#pragma once
// Points and boxes in world coordinates (metres, Z-up).

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

namespace ispars {

/// A point or direction in world coordinates, in metres.
using Vec3 = Eigen::Vector3d;

/// An axis-aligned box, closed on every side; the sampling region of the robot's centre.
struct Aabb {
  Vec3 min = Vec3::Zero();
  Vec3 max = Vec3::Zero();

  /// True when p lies inside the box or on its boundary.
  [[nodiscard]] bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  /// Side lengths of the box.
  [[nodiscard]] Vec3 extent() const { return max - min; }
};

}  // namespace ispars
