// The exact primitives against dense sampling (an independent upper bound that converges).

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/planning/geometry/distance.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

Triangle random_triangle(scene_files::Rng& rng) {
  return {rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)}), rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)}),
          rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)})};
}

// min over a barycentric grid of n steps per side: >= the exact distance, and within the grid's
// spacing of it.
double sampled_point_triangle_distance(const Vec3& p, const Triangle& t, int n) {
  double best = INFINITY;
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; i + j <= n; ++j) {
      const double u = static_cast<double>(i) / n;
      const double v = static_cast<double>(j) / n;
      best = std::min(best, (p - (t.a + u * (t.b - t.a) + v * (t.c - t.a))).norm());
    }
  }
  return best;
}

double longest_edge(const Triangle& t) {
  return std::max({(t.b - t.a).norm(), (t.c - t.b).norm(), (t.a - t.c).norm()});
}

TEST(Distance, PointTriangleMatchesSampling) {
  scene_files::Rng rng(1);
  for (int k = 0; k < 300; ++k) {
    const Triangle t = random_triangle(rng);
    const Vec3 p = rng.uniform_in({Vec3(-2, -2, -2), Vec3(2, 2, 2)});
    const double exact = std::sqrt(point_triangle_distance_squared(p, t));
    const int n = 200;
    const double sampled = sampled_point_triangle_distance(p, t, n);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - longest_edge(t) / n);
  }
}

TEST(Distance, ClosestPointLiesOnTheTriangle) {
  scene_files::Rng rng(2);
  for (int k = 0; k < 1000; ++k) {
    const Triangle t = random_triangle(rng);
    const Vec3 p = rng.uniform_in({Vec3(-2, -2, -2), Vec3(2, 2, 2)});
    const Vec3 c = closest_point_on_triangle(p, t);
    EXPECT_LE(point_triangle_distance_squared(c, t), 1e-20);
    EXPECT_NEAR((p - c).squaredNorm(), point_triangle_distance_squared(p, t), 1e-12);
  }
}

TEST(Distance, SegmentTriangleMatchesSamplingAlongTheSegment) {
  scene_files::Rng rng(3);
  int intersecting = 0;
  for (int k = 0; k < 300; ++k) {
    const Triangle t = random_triangle(rng);
    Vec3 s0 = rng.uniform_in({Vec3(-2, -2, -2), Vec3(2, 2, 2)});
    Vec3 s1 = rng.uniform_in({Vec3(-2, -2, -2), Vec3(2, 2, 2)});
    if (k % 4 == 0) {  // a quarter pass through an interior point of the triangle
      const Vec3 inside = (t.a + t.b + t.c) / 3.0;
      s1 = inside + (inside - s0);
    }
    const double exact = std::sqrt(segment_triangle_distance_squared(s0, s1, t));
    // Point-triangle distance is 1-Lipschitz along the segment: sampling at n steps is within
    // |s1 - s0| / (2n) of the true minimum.
    const int n = 4000;
    double sampled = INFINITY;
    for (int i = 0; i <= n; ++i) {
      const Vec3 p = s0 + (s1 - s0) * (static_cast<double>(i) / n);
      sampled = std::min(sampled, std::sqrt(point_triangle_distance_squared(p, t)));
    }
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - (s1 - s0).norm() / (2.0 * n) - 1e-12);
    intersecting += exact == 0.0;
  }
  EXPECT_GE(intersecting, 75);  // the sample covers the crossing case too
}

TEST(Distance, SegmentSegmentMatchesSampling) {
  scene_files::Rng rng(4);
  for (int k = 0; k < 300; ++k) {
    const Vec3 p0 = rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    const Vec3 p1 = rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    const Vec3 q0 = rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)});
    const Vec3 q1 = k % 10 == 0 ? Vec3(q0 + (p1 - p0)) : rng.uniform_in({Vec3(-1, -1, -1), Vec3(1, 1, 1)});  // parallel
    const double exact = std::sqrt(segment_segment_distance_squared(p0, p1, q0, q1));
    const int n = 4000;
    double sampled = INFINITY;
    for (int i = 0; i <= n; ++i) {
      const Vec3 p = p0 + (p1 - p0) * (static_cast<double>(i) / n);
      sampled = std::min(sampled, std::sqrt(point_segment_distance_squared(p, q0, q1)));
    }
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - (p1 - p0).norm() / (2.0 * n) - 1e-12);
  }
}

TEST(Distance, DegenerateTrianglesBehaveAsTheirEdges) {
  const Triangle line{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  EXPECT_NEAR(point_triangle_distance_squared(Vec3(1, 1, 0), line), 1.0, 1e-15);
  EXPECT_NEAR(point_triangle_distance_squared(Vec3(3, 0, 0), line), 1.0, 1e-15);
  const Triangle dot{Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)};
  EXPECT_NEAR(point_triangle_distance_squared(Vec3(1, 1, 3), dot), 4.0, 1e-15);
  EXPECT_NEAR(segment_triangle_distance_squared(Vec3(1, -1, 0.5), Vec3(1, 1, 0.5), line), 0.25, 1e-15);
  EXPECT_FALSE(segment_intersects_triangle(Vec3(1, 0, -1), Vec3(1, 0, 1), line));
  EXPECT_EQ(segment_triangle_distance_squared(Vec3(1, 0, -1), Vec3(1, 0, 1), line), 0.0);
}

TEST(Distance, SegmentInTheTrianglePlaneCrossingItsInterior) {
  const Triangle t{Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
  EXPECT_EQ(segment_triangle_distance_squared(Vec3(-1, 0.5, 0), Vec3(3, 0.5, 0), t), 0.0);
  EXPECT_EQ(segment_triangle_distance_squared(Vec3(0.2, 0.2, 0), Vec3(0.3, 0.3, 0), t), 0.0);
}

TEST(Distance, RayPlaneCrossingReportsMargin) {
  const Triangle t{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  const auto inside = ray_plane_crossing(Vec3(0.25, 0.25, 1), Vec3(0, 0, -1), t);
  ASSERT_TRUE(inside);
  EXPECT_NEAR(inside->s, 1.0, 1e-15);
  EXPECT_NEAR(inside->margin, 0.25, 1e-15);
  const auto outside = ray_plane_crossing(Vec3(2, 2, 1), Vec3(0, 0, -1), t);
  ASSERT_TRUE(outside);
  EXPECT_LT(outside->margin, 0.0);
  EXPECT_FALSE(ray_plane_crossing(Vec3(0, 0, 1), Vec3(1, 0, 0), t));  // parallel
}

}  // namespace
}  // namespace ispars::planning
