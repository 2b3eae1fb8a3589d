// The independent check of a flown tour (flown_tour_check.hpp): what a stop sees comes from rays
// cast now, every segment from the collision checker; a stop moved out of view, a segment through
// a wall, a wrong cost or an open path each fail it, named.

#include <gtest/gtest.h>

#include "ispars/planning/tour/flown_tour_check.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// A stop that sees every POI of the open scene (its POIs lie on the far tile at z = 40).
Vec3 viewpoint_of_all(const Scene& scene) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : scene.pois()) centre += p;
  return centre / static_cast<double>(scene.pois().size()) + Vec3(0, 0, -0.5);
}

std::vector<PoiId> all_pois(const Scene& scene) {
  std::vector<PoiId> ids(scene.pois().size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<PoiId>(i);
  return ids;
}

double length(const std::vector<Vec3>& stops) {
  double l = 0.0;
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) l += (stops[i + 1] - stops[i]).norm();
  return l;
}

TEST(FlownTourCheck, ASoundTourPassesAndSaysWhatEachStopSees) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  const std::vector<Vec3> stops{root, viewpoint_of_all(scene), root};
  const FlownTourCheck c = check_flown_tour(scene, root, targets, stops, length(stops));
  EXPECT_TRUE(c.valid()) << c.problem;
  ASSERT_EQ(c.sees.size(), 3u);
  EXPECT_EQ(c.sees[1], targets);
  EXPECT_TRUE(c.sees[0].empty());
  EXPECT_EQ(c.missing_targets, 0u);
}

TEST(FlownTourCheck, AStopMovedOutOfViewFailsNamingTheTarget) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  std::vector<Vec3> stops{root, viewpoint_of_all(scene), root};
  stops[1] += Vec3(0, 0, -5);  // beyond the sensor's range of every POI
  const FlownTourCheck c = check_flown_tour(scene, root, targets, stops, length(stops));
  EXPECT_FALSE(c.valid());
  EXPECT_EQ(c.missing_targets, targets.size());
  EXPECT_TRUE(test::mentions(c.problem, "targets are seen from no stop (the first: POI 0)")) << c.problem;
}

TEST(FlownTourCheck, ASegmentThroughAWallAnOpenPathAndAWrongCostFail) {
  const Scene scene = test::open_scene(1.0, 1.5, /*wall=*/true);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  const Vec3 view = viewpoint_of_all(scene);
  // Through the wall at x = 2.5: root -> (5, 0, 0) crosses it.
  const std::vector<Vec3> through{root, Vec3(5, 0, 0), view, root};
  FlownTourCheck c = check_flown_tour(scene, root, targets, through, length(through));
  EXPECT_TRUE(test::mentions(c.problem, "the segment from stop 0 to stop 1 is not collision-free")) << c.problem;
  const std::vector<Vec3> open{root, view};
  c = check_flown_tour(scene, root, targets, open, length(open));
  EXPECT_TRUE(test::mentions(c.problem, "does not start and end at the root")) << c.problem;
}

TEST(FlownTourCheck, AWrongCostAndAStopInCollisionFail) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  const Vec3 view = viewpoint_of_all(scene);
  const std::vector<Vec3> sound{root, view, root};
  FlownTourCheck c = check_flown_tour(scene, root, targets, sound, length(sound) * 0.9);
  EXPECT_TRUE(test::mentions(c.problem, "is not the segments' length")) << c.problem;
  const std::vector<Vec3> inside{root, Vec3(40.3, 40.3, 40.0), view, root};  // a stop on the tile
  c = check_flown_tour(scene, root, targets, inside, length(inside));
  EXPECT_TRUE(test::mentions(c.problem, "stop 1 at (40.3000, 40.3000, 40.0000) is not a valid configuration"))
      << c.problem;
}

}  // namespace
}  // namespace ispars::planning
