// Viewpoint refinement (viewpoint_refinement.hpp): stops move where they shorten the tour, keep in
// view what only they see, go when nothing needs them; the path never grows, never loses a target
// and never crosses the structure (each result passes the independent check).

#include <gtest/gtest.h>

#include <stdexcept>

#include "ispars/planning/tour/flown_tour_check.hpp"
#include "ispars/planning/tour/viewpoint_refinement.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

std::vector<PoiId> all_pois(const Scene& scene) {
  std::vector<PoiId> ids(scene.pois().size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<PoiId>(i);
  return ids;
}

Vec3 centroid(const std::vector<Vec3>& points) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : points) c += p;
  return c / static_cast<double>(points.size());
}

TEST(ViewpointRefinement, AFarStopMovesTowardTheRootAndStillSeesItsTargets) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  // Seen from 0.6 below the tile's POIs; the sensor reaches 1, so the stop can come nearer the root.
  std::vector<Vec3> stops{root, centroid(scene.pois()) + Vec3(0, 0, -0.3), root};
  const double before = path_length(stops);
  RefineOptions o;
  o.draws = 64;
  const RefineResult r = refine_viewpoints(scene, targets, stops, o);
  EXPECT_GE(r.moved, 1u);
  EXPECT_LT(path_length(stops), before - 0.1) << "a stop 0.3 inside the sensor's reach gains on both legs";
  const FlownTourCheck c = check_flown_tour(scene, root, targets, stops, path_length(stops));
  EXPECT_TRUE(c.valid()) << c.problem;
}

TEST(ViewpointRefinement, AStopWhoseTargetsOthersSeeIsDroppedAndTheSameSeedGivesTheSamePath) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  const std::vector<PoiId> targets = all_pois(scene);
  const Vec3 view = centroid(scene.pois()) + Vec3(0, 0, -0.3);
  std::vector<Vec3> stops{root, view, view + Vec3(0, 0, -0.05), root};  // the second sees what the first does
  std::vector<Vec3> again = stops;
  const RefineResult r = refine_viewpoints(scene, targets, stops);
  (void)refine_viewpoints(scene, targets, again);
  EXPECT_GE(r.dropped, 1u);
  EXPECT_EQ(stops, again);
  EXPECT_TRUE(check_flown_tour(scene, root, targets, stops, path_length(stops)).valid());
}

TEST(ViewpointRefinement, WithNothingToSeeEveryStopGoes) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  std::vector<Vec3> stops{root, Vec3(-2, 2, 0), Vec3(-2, -2, 0), Vec3(-4, 2, 0), Vec3(-4, -2, 0), root};
  const RefineResult r = refine_viewpoints(scene, {}, stops);
  EXPECT_EQ(r.dropped, 4u);
  EXPECT_EQ(stops, (std::vector<Vec3>{root, root}));
}

TEST(ViewpointRefinement, ADetourAroundAWallShortensWithoutCrossingIt) {
  const Scene scene = test::open_scene(1.0, 1.5, /*wall=*/true);
  const Vec3 root = scene.config().root;
  // Around the wall at x = 2.5 (|y|, |z| <= 1) to (5, 0, 0) and back: at first no stop can go (each
  // stop's neighbours are joined only through the wall); moves must go around it.
  std::vector<Vec3> stops{root, Vec3(2.5, 3, 0), Vec3(5, 0, 0), Vec3(2.5, -3, 0), root};
  const double before = path_length(stops);
  RefineOptions o;
  o.draws = 64;
  const RefineResult r = refine_viewpoints(scene, {}, stops, o);
  EXPECT_GE(r.moved, 1u);
  EXPECT_LT(path_length(stops), before);
  const FlownTourCheck c = check_flown_tour(scene, root, {}, stops, path_length(stops));
  EXPECT_TRUE(c.valid()) << c.problem;
}

TEST(ViewpointRefinement, AnOpenPathOrAnUnseenTargetIsRefused) {
  const Scene scene = test::open_scene(1.0, 1.5);
  const Vec3 root = scene.config().root;
  std::vector<Vec3> open{root, Vec3(1, 0, 0)};
  EXPECT_THROW((void)refine_viewpoints(scene, {}, open), std::invalid_argument);
  std::vector<Vec3> blind{root, Vec3(1, 0, 0), root};
  const std::vector<PoiId> targets{0};
  EXPECT_THROW((void)refine_viewpoints(scene, targets, blind), std::invalid_argument);
}

}  // namespace
}  // namespace ispars::planning
