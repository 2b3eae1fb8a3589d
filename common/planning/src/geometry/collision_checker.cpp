#include "ispars/planning/geometry/collision_checker.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace ispars::planning {
namespace {

// Embree culls BVH nodes against the query sphere in single precision. Padding the sphere by
// more than the float rounding of its centre makes the culling conservative, so the exact
// double-precision test below sees every triangle that could be within the radius.
float padded_radius(double radius, const Vec3& centre) {
  const double pad = 1e-5 * (1.0 + centre.cwiseAbs().maxCoeff());
  return static_cast<float>(radius + pad);
}

RTCPointQuery make_query(const Vec3& centre, float radius) {
  RTCPointQuery query;
  query.x = static_cast<float>(centre.x());
  query.y = static_cast<float>(centre.y());
  query.z = static_cast<float>(centre.z());
  query.time = 0.0f;
  query.radius = radius;
  return query;
}

// Ends the query at the first triangle within the radius of a point (a == b) or of the segment
// piece [a, b]; kSegment picks the exact distance at compile time, keeping the point check lean.
struct TouchProbe {
  const EmbreeScene* scene;
  Vec3 a;
  Vec3 b;
  double radius_squared;
  bool touched = false;
};

template <bool kSegment>
bool touch_probe_callback(RTCPointQueryFunctionArguments* args) {
  auto* probe = static_cast<TouchProbe*>(args->userPtr);
  if (probe->touched) return false;
  const Triangle& t = probe->scene->triangle(args->primID);
  const double d2 = kSegment ? segment_triangle_distance_squared(probe->a, probe->b, t)
                             : point_triangle_distance_squared(probe->a, t);
  if (d2 <= probe->radius_squared) {
    probe->touched = true;
    args->query->radius = 0.0f;  // nothing more to learn: shrink the search to nothing
    return true;
  }
  return false;
}

// Exact nearest distance: shrink the query sphere to each closer triangle found.
struct NearestProbe {
  const EmbreeScene* scene;
  Vec3 centre;
  double best_squared = INFINITY;
};

bool nearest_probe_callback(RTCPointQueryFunctionArguments* args) {
  auto* probe = static_cast<NearestProbe*>(args->userPtr);
  const Triangle& t = probe->scene->triangle(args->primID);
  const double d2 = point_triangle_distance_squared(probe->centre, t);
  if (d2 < probe->best_squared) {
    probe->best_squared = d2;
    args->query->radius = padded_radius(std::sqrt(d2), probe->centre);
    return true;
  }
  return false;
}

}  // namespace

CollisionChecker::CollisionChecker(std::shared_ptr<const EmbreeScene> scene, Aabb bounds, double robot_radius)
    : scene_(std::move(scene)), bounds_(bounds), radius_(robot_radius) {}

bool CollisionChecker::point_valid(const Vec3& q) const {
  counters_.add_point();
  if (!bounds_.contains(q)) return false;
  TouchProbe probe{scene_.get(), q, q, radius_ * radius_};
  RTCPointQuery query = make_query(q, padded_radius(radius_, q));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_->handle(), &query, &context, touch_probe_callback<false>, &probe);
  return !probe.touched;
}

bool CollisionChecker::segment_valid(const Vec3& a, const Vec3& b) const {
  counters_.add_segment();
  if (!bounds_.contains(a) || !bounds_.contains(b)) return false;  // the box is convex
  return capsule_free(a, b);
}

bool CollisionChecker::capsule_free(const Vec3& a, const Vec3& b) const {
  // Cover the capsule with the bounding spheres of short pieces of the segment (each piece at
  // most one diameter long), so the BVH culls tightly around the capsule. Each piece's candidates
  // get the exact segment-triangle distance; any triangle within r of the whole segment is within
  // r of some piece and inside that piece's sphere, so nothing is missed.
  const double length = (b - a).norm();
  const int pieces = std::max(1, static_cast<int>(std::ceil(length / (2.0 * radius_))));
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  for (int i = 0; i < pieces; ++i) {
    const Vec3 p0 = a + (b - a) * (static_cast<double>(i) / pieces);
    const Vec3 p1 = i + 1 == pieces ? b : Vec3(a + (b - a) * (static_cast<double>(i + 1) / pieces));
    const Vec3 centre = 0.5 * (p0 + p1);
    TouchProbe probe{scene_.get(), p0, p1, radius_ * radius_};
    RTCPointQuery query = make_query(centre, padded_radius(0.5 * (p1 - p0).norm() + radius_, centre));
    rtcPointQuery(scene_->handle(), &query, &context, touch_probe_callback<true>, &probe);
    if (probe.touched) return false;
  }
  return true;
}

double CollisionChecker::distance_to_surface(const Vec3& q) const {
  NearestProbe probe{scene_.get(), q};
  RTCPointQuery query = make_query(q, INFINITY);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_->handle(), &query, &context, nearest_probe_callback, &probe);
  return std::sqrt(probe.best_squared);
}

}  // namespace ispars::planning
