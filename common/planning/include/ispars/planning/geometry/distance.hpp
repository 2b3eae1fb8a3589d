#pragma once
// Exact distance and intersection primitives in double precision.
//
// These are the ground truth for every collision and visibility query: the fast paths run them
// on the candidates a bounding-volume hierarchy returns, and the brute-force references run them
// on every triangle. Degenerate (zero-area) triangles are handled as their three edges.

#include <optional>

#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// A triangle with double-precision corners.
struct Triangle {
  Vec3 a, b, c;
};

/// The point of triangle t closest to p (Ericson, Real-Time Collision Detection, 5.1.5).
[[nodiscard]] Vec3 closest_point_on_triangle(const Vec3& p, const Triangle& t);

/// Squared distance from p to the closed triangle t.
[[nodiscard]] double point_triangle_distance_squared(const Vec3& p, const Triangle& t);

/// Squared distance from p to the closed segment [a, b].
[[nodiscard]] double point_segment_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b);

/// Squared distance between the closed segments [p0, p1] and [q0, q1] (Ericson 5.1.9).
[[nodiscard]] double segment_segment_distance_squared(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

/// True when the closed segment [s0, s1] crosses or touches the interior of triangle t.
/// Degenerate triangles never intersect here; the edge distances cover them.
[[nodiscard]] bool segment_intersects_triangle(const Vec3& s0, const Vec3& s1, const Triangle& t);

/// Squared distance between the closed segment [s0, s1] and the closed triangle t: zero when
/// they intersect, else the least of the endpoint-to-triangle and segment-to-edge distances.
[[nodiscard]] double segment_triangle_distance_squared(const Vec3& s0, const Vec3& s1, const Triangle& t);

/// Where a ray origin + s * direction (s >= 0) meets triangle t, with the smallest barycentric
/// coordinate of the hit: a margin, negative when the ray passes outside the triangle.
struct RayTriangleHit {
  double s = 0.0;       ///< Ray parameter of the plane crossing.
  double margin = 0.0;  ///< min(u, v, 1 - u - v) at the crossing; >= 0 means inside.
};

/// The ray's crossing of the triangle's plane with its barycentric margin, or nothing when the
/// ray is parallel to the plane or the triangle is degenerate. The caller decides what margin
/// counts as a hit, which lets tests name the near-edge cases where float and double may differ.
[[nodiscard]] std::optional<RayTriangleHit> ray_plane_crossing(const Vec3& origin, const Vec3& direction,
                                                               const Triangle& t);

}  // namespace ispars::planning
