// The reference itself, on cases whose answers are known by hand.

#include <gtest/gtest.h>

#include "ispars/reference/brute_force.hpp"

namespace ispars::reference {
namespace {

BruteForceGeometry unit_square_reference() {
  // A unit square in z = 0, a POI above it and one under it.
  const std::vector<planning::Triangle> triangles{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0)},
                                                  {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)}};
  return BruteForceGeometry(triangles, {Vec3(-5, -5, -5), Vec3(5, 5, 5)}, 0.25, {Vec3(0.5, 0.5, 1), Vec3(0.3, 0.6, -1)},
                            3.0);
}

TEST(BruteForce, DistancesAndValidity) {
  const auto ref = unit_square_reference();
  EXPECT_DOUBLE_EQ(ref.distance_to_surface(Vec3(0.5, 0.5, 2)), 2.0);
  EXPECT_DOUBLE_EQ(ref.distance_to_surface(Vec3(2, 0.5, 0)), 1.0);
  EXPECT_TRUE(ref.point_valid(Vec3(0.5, 0.5, 0.3)));
  EXPECT_FALSE(ref.point_valid(Vec3(0.5, 0.5, 0.25)));
  EXPECT_FALSE(ref.point_valid(Vec3(0.5, 0.5, 6)));  // outside the bounds
  EXPECT_DOUBLE_EQ(ref.segment_distance_to_surface(Vec3(-1, 0.5, 0.5), Vec3(2, 0.5, 0.5)), 0.5);
  EXPECT_FALSE(ref.segment_valid(Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1)));
  EXPECT_TRUE(ref.segment_valid(Vec3(-1, 0.5, 0.3), Vec3(2, 0.5, 0.3)));
}

TEST(BruteForce, LineOfSightAndTheToleranceBand) {
  const auto ref = unit_square_reference();
  EXPECT_EQ(ref.visible_pois(Vec3(0.5, 0.5, 2)), (std::vector<PoiId>{0}));
  EXPECT_EQ(ref.visible_pois(Vec3(0.5, 0.5, -2)), (std::vector<PoiId>{1}));
  // A sight line through the square's diagonal edge is visible-or-not by a hair: flagged.
  const ReferenceSight grazing = ref.line_of_sight(Vec3(0.6, 0.6, -1), 0);
  EXPECT_TRUE(grazing.ambiguous);
  const ReferenceSight clear = ref.line_of_sight(Vec3(0.5, 0.5, 2), 0);
  EXPECT_TRUE(clear.visible);
  EXPECT_FALSE(clear.ambiguous);
}

}  // namespace
}  // namespace ispars::reference
