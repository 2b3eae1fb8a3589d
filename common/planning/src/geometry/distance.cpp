#include "ispars/planning/geometry/distance.hpp"

#include <algorithm>
#include <cmath>

namespace ispars::planning {
namespace {

// A triangle whose cross product is this small relative to its edge lengths has no usable
// interior: its barycentric solve would divide by ~0, so it is handled through its edges.
bool is_degenerate(const Triangle& t) {
  const Vec3 ab = t.b - t.a;
  const Vec3 ac = t.c - t.a;
  const double scale = std::max({ab.squaredNorm(), ac.squaredNorm(), (t.c - t.b).squaredNorm()});
  return ab.cross(ac).squaredNorm() <= 1e-24 * scale * scale;
}

double edges_distance_squared(const Vec3& p, const Triangle& t) {
  return std::min({point_segment_distance_squared(p, t.a, t.b), point_segment_distance_squared(p, t.b, t.c),
                   point_segment_distance_squared(p, t.c, t.a)});
}

}  // namespace

Vec3 closest_point_on_triangle(const Vec3& p, const Triangle& t) {
  const Vec3& a = t.a;
  const Vec3& b = t.b;
  const Vec3& c = t.c;
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;

  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;

  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) {
    // Degenerate triangle that reached the face region: take the nearest edge point.
    Vec3 best = a;
    double best_d2 = INFINITY;
    const Vec3* corners[3] = {&a, &b, &c};
    for (int i = 0; i < 3; ++i) {
      const Vec3& u = *corners[i];
      const Vec3& v = *corners[(i + 1) % 3];
      const Vec3 uv = v - u;
      const double len2 = uv.squaredNorm();
      const double s = len2 > 0.0 ? std::clamp((p - u).dot(uv) / len2, 0.0, 1.0) : 0.0;
      const Vec3 q = u + s * uv;
      const double q_d2 = (p - q).squaredNorm();
      if (q_d2 < best_d2) {
        best_d2 = q_d2;
        best = q;
      }
    }
    return best;
  }
  const double v = vb / denom;
  const double w = vc / denom;
  return a + ab * v + ac * w;
}

double point_triangle_distance_squared(const Vec3& p, const Triangle& t) {
  if (is_degenerate(t)) return edges_distance_squared(p, t);
  return (p - closest_point_on_triangle(p, t)).squaredNorm();
}

double point_segment_distance_squared(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return (p - a).squaredNorm();
  const double s = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + s * ab)).squaredNorm();
}

double segment_segment_distance_squared(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const double a = d1.squaredNorm();
  const double e = d2.squaredNorm();
  const double f = d2.dot(r);
  double s = 0.0;
  double u = 0.0;
  if (a <= 0.0 && e <= 0.0) return r.squaredNorm();
  if (a <= 0.0) {
    u = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      u = (b * s + f) / e;
      if (u < 0.0) {
        u = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (u > 1.0) {
        u = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + u * d2)).squaredNorm();
}

std::optional<RayTriangleHit> ray_plane_crossing(const Vec3& origin, const Vec3& direction, const Triangle& t) {
  if (is_degenerate(t)) return std::nullopt;
  // Barycentric coordinates from signed volumes, solved in double.
  const Vec3 e1 = t.b - t.a;
  const Vec3 e2 = t.c - t.a;
  const Vec3 n = e1.cross(e2);
  const double denom = n.dot(direction);
  if (denom == 0.0) return std::nullopt;
  const double s = n.dot(t.a - origin) / denom;
  const Vec3 x = origin + s * direction;
  const double n2 = n.squaredNorm();
  const double u = n.dot((t.c - t.b).cross(x - t.b)) / n2;  // weight of a
  const double v = n.dot((t.a - t.c).cross(x - t.c)) / n2;  // weight of b
  const double w = 1.0 - u - v;                             // weight of c
  return RayTriangleHit{s, std::min({u, v, w})};
}

bool segment_intersects_triangle(const Vec3& s0, const Vec3& s1, const Triangle& t) {
  const auto crossing = ray_plane_crossing(s0, s1 - s0, t);
  return crossing && crossing->s >= 0.0 && crossing->s <= 1.0 && crossing->margin >= 0.0;
}

double segment_triangle_distance_squared(const Vec3& s0, const Vec3& s1, const Triangle& t) {
  if (segment_intersects_triangle(s0, s1, t)) return 0.0;
  double best = std::min(point_triangle_distance_squared(s0, t), point_triangle_distance_squared(s1, t));
  best = std::min(best, segment_segment_distance_squared(s0, s1, t.a, t.b));
  best = std::min(best, segment_segment_distance_squared(s0, s1, t.b, t.c));
  best = std::min(best, segment_segment_distance_squared(s0, s1, t.c, t.a));
  return best;
}

}  // namespace ispars::planning
