// FCL's sphere and capsule collision agree with the exact reference away from the boundary.

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/reference/brute_force.hpp"
#include "ispars/reference/fcl_checker.hpp"
#include "support/test_support.hpp"

namespace ispars::reference {
namespace {

TEST(FclCollisionChecker, AgreesWithReferenceOnRealMeshes) {
  for (const std::string name : {"water_tower", "truss_bridge"}) {
    const planning::Scene& scene = test::shared_scene(name);
    const double r = scene.config().robot_radius;
    const FclCollisionChecker fcl(scene.mesh(), scene.config().bounds, r);
    const BruteForceGeometry brute(scene.embree().triangles(), scene.config().bounds, r, scene.pois(),
                                   scene.config().sensor_range);
    scene_files::Rng rng(31);
    // FCL works to its own tolerance (GJK/EPA); compare where the answer is clear by 1e-6 m.
    for (const Vec3& p : test::mixed_query_points(scene, rng, test::scaled(1500))) {
      const double d = brute.distance_to_surface(p);
      if (std::abs(d - r) < 1e-6) continue;
      EXPECT_EQ(fcl.point_valid(p), scene.config().bounds.contains(p) && d > r) << name << " " << p.transpose();
    }
    for (const auto& s : test::mixed_query_segments(scene, rng, test::scaled(1500))) {
      const double d = brute.segment_distance_to_surface(s.a, s.b);
      if (std::abs(d - r) < 1e-6) continue;
      EXPECT_EQ(fcl.segment_valid(s.a, s.b), d > r) << name << " " << s.a.transpose() << " -> " << s.b.transpose();
    }
  }
}

}  // namespace
}  // namespace ispars::reference
