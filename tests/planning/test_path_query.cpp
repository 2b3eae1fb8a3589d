// plan_path (path_query.hpp) on a hand-made roadmap over open_scene's wall (x = 2.5, |y|, |z| <= 1,
// robot radius 0.1): joins within Delta by free segments, the shortest route, the direct segment,
// and each input error named by its field.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/search/path_query.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

const Scene& wall_scene() {
  static const Scene scene = test::open_scene(1.0, 2.0, true);
  return scene;
}

// 0 (0,0,0) - 1 (2,0,1.5) - 2 (3,0,1.5) - 3 (5,0,0): over the wall's top edge, edges 2.5, 1, 2.5.
// 4 (0,-5,0) alone in its own component.
Roadmap over_the_wall() {
  Roadmap r(wall_scene().pois().size());
  const std::vector<PoiId> none;
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(2, 0, 1.5), Vec3(3, 0, 1.5), Vec3(5, 0, 0), Vec3(0, -5, 0)}) {
    r.add_vertex(p, none);
  }
  r.add_edge(0, 1);
  r.add_edge(1, 2);
  r.add_edge(2, 3);
  return r;
}

// Runs plan_path and returns the InputError it throws ("" fields when it does not throw).
params::InputError error_of(const Roadmap& r, const Vec3& from, const Vec3& to, double radius = 2.0) {
  try {
    (void)plan_path(wall_scene(), r, from, to, radius);
  } catch (const params::InputError& e) {
    return e;
  }
  return params::InputError("", "", "no error");
}

using test::mentions;

TEST(PathQuery, RouteThroughTheRoadmapFromTheJoinsWithin) {
  const Roadmap r = over_the_wall();
  const RoadmapPath p = plan_path(wall_scene(), r, Vec3(0.5, 0, 0), Vec3(4.5, 0, 0), 2.0);
  EXPECT_EQ(p.vertices, (std::vector<VertexId>{0, 1, 2, 3}));
  ASSERT_EQ(p.waypoints.size(), 6u);
  EXPECT_EQ(p.waypoints.front(), Vec3(0.5, 0, 0));
  EXPECT_EQ(p.waypoints[2], Vec3(2, 0, 1.5));
  EXPECT_EQ(p.waypoints.back(), Vec3(4.5, 0, 0));
  EXPECT_DOUBLE_EQ(p.length, 0.5 + 2.5 + 1 + 2.5 + 0.5);
  for (std::size_t i = 1; i < p.waypoints.size(); ++i) {
    EXPECT_TRUE(wall_scene().segment_valid(p.waypoints[i - 1], p.waypoints[i])) << "segment " << i;
  }
}

TEST(PathQuery, AJoinWithinDeltaWhoseSegmentIsBlockedIsNotUsed) {
  // Either side of the wall, 0.6 apart: the direct segment is blocked, and so are the joins
  // (2.2,0,0)-2 and (2.8,0,0)-1; the path runs 1-2 over the top.
  const Roadmap r = over_the_wall();
  const RoadmapPath p = plan_path(wall_scene(), r, Vec3(2.2, 0, 0), Vec3(2.8, 0, 0), 2.0);
  EXPECT_EQ(p.vertices, (std::vector<VertexId>{1, 2}));
  EXPECT_NEAR(p.length, 2 * std::sqrt(0.04 + 2.25) + 1.0, 1e-12);
}

TEST(PathQuery, PointsInViewWithinDeltaGoStraight) {
  const Roadmap r = over_the_wall();
  const RoadmapPath p = plan_path(wall_scene(), r, Vec3(0.5, 0, 0), Vec3(1.5, 0, 0.5), 2.0);
  EXPECT_TRUE(p.vertices.empty());
  EXPECT_EQ(p.waypoints, (std::vector<Vec3>{Vec3(0.5, 0, 0), Vec3(1.5, 0, 0.5)}));
  EXPECT_DOUBLE_EQ(p.length, std::sqrt(1.25));
  // In view but farther apart than Delta: through the roadmap (here vertex 0 then 1).
  const RoadmapPath far = plan_path(wall_scene(), r, Vec3(-0.5, 0, 0), Vec3(1.9, 0, 1.2), 2.0);
  EXPECT_FALSE(far.vertices.empty());
}

TEST(PathQuery, TheBestJoinsAreChosenByTotalLength) {
  // From (1, 0, 0.6): vertex 0 is the nearer join (1.17, against 1.35 to vertex 1), but
  // starting at vertex 1 is shorter in all (5.35 against 7.67).
  const Roadmap r = over_the_wall();
  const RoadmapPath p = plan_path(wall_scene(), r, Vec3(1, 0, 0.6), Vec3(4.5, 0, 0), 2.0);
  EXPECT_EQ(p.vertices, (std::vector<VertexId>{1, 2, 3}));
  EXPECT_NEAR(p.length, std::sqrt(1.81) + 1 + 2.5 + 0.5, 1e-12);
}

TEST(PathQuery, BadPointsAreNamedByTheirField) {
  const Roadmap r = over_the_wall();
  const Vec3 good(0.5, 0, 0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const params::InputError not_finite = error_of(r, Vec3(nan, 0, 0), good);
  EXPECT_EQ(not_finite.file(), "path");
  EXPECT_EQ(not_finite.field(), "from");
  EXPECT_TRUE(mentions(not_finite.problem(), "finite")) << not_finite.what();

  const params::InputError collision = error_of(r, good, Vec3(2.5, 0, 0));
  EXPECT_EQ(collision.field(), "to");
  EXPECT_TRUE(mentions(collision.problem(), "in collision")) << collision.what();

  const params::InputError outside = error_of(r, Vec3(60, 0, 0), good);
  EXPECT_EQ(outside.field(), "from");
  EXPECT_TRUE(mentions(outside.problem(), "outside the scene bounds")) << outside.what();

  const params::InputError lonely = error_of(r, good, Vec3(20, 20, 0));
  EXPECT_EQ(lonely.field(), "to");
  EXPECT_TRUE(mentions(lonely.problem(), "no free segment to a roadmap vertex within Delta = 2 (0 vertices"))
      << lonely.what();
}

TEST(PathQuery, AllJoinsBlockedIsNamedWithTheVerticesWithinDelta) {
  Roadmap r(wall_scene().pois().size());
  r.add_vertex(Vec3(3, 0, 0), std::vector<PoiId>{});
  const params::InputError e = error_of(r, Vec3(2, 0, 0), Vec3(3.5, 0, 0));
  EXPECT_EQ(e.field(), "from");
  EXPECT_TRUE(mentions(e.problem(), "(1 vertices within it)")) << e.what();
}

TEST(PathQuery, JoinsInDifferentComponentsHaveNoPath) {
  const Roadmap r = over_the_wall();
  const params::InputError e = error_of(r, Vec3(0, -4.5, 0), Vec3(4.5, 0, 0));
  EXPECT_EQ(e.file(), "path");
  EXPECT_EQ(e.field(), "to");
  EXPECT_TRUE(mentions(e.problem(), "different component")) << e.what();
}

}  // namespace
}  // namespace ispars::planning
