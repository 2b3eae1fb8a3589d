// ros2_markers: what a ROS 2 viewer is sent of a roadmap and a tour, checked field by field on a
// roadmap small enough to know by heart; and the ROS names scenes are given.

#include "ispars/ros2/ros2_markers.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace ispars::ros2 {
namespace {

const auto kStamp =
    std::chrono::system_clock::time_point(std::chrono::seconds(1'700'000'000)) + std::chrono::nanoseconds(250'000'000);

TEST(Ros2Names, ASceneNameBecomesOneRosNameToken) {
  EXPECT_EQ(ros_token("s0"), "s0");
  EXPECT_EQ(ros_token("bridge_n1000"), "bridge_n1000");
  EXPECT_EQ(ros_token("bridge-n1000"), "bridge_n1000");
  EXPECT_EQ(ros_token("tank..tower"), "tank_tower") << "a run of separators is one '_'";
  EXPECT_EQ(ros_token("_x_"), "x") << "none at either end";
  EXPECT_EQ(ros_token("9lives"), "scene_9lives") << "a token may not start with a digit";
  EXPECT_EQ(ros_token("--"), "scene");
  EXPECT_EQ(roadmap_topic("s0"), "rt/ispars/s0/roadmap");
  EXPECT_EQ(tour_topic("s0"), "rt/ispars/s0/tour");
}

TEST(Ros2Markers, ARoadmapIsItsVerticesItsEdgesAndItsPoisSeenOrNot) {
  Roadmap roadmap(3);
  const std::vector<PoiId> sees_one{1};
  roadmap.add_vertex(Vec3(0, 0, 0), sees_one);
  roadmap.add_vertex(Vec3(10, 0, 0), {});
  roadmap.add_vertex(Vec3(10, 5, 2), {});
  ASSERT_TRUE(roadmap.add_edge(0, 1));
  ASSERT_TRUE(roadmap.add_edge(1, 2));
  const std::vector<Vec3> pois{{1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  const MarkerArray array = roadmap_markers(roadmap, pois, "world", kStamp);
  ASSERT_EQ(array.markers().size(), 3u);
  const auto& vertices = array.markers()[0];
  const auto& edges = array.markers()[1];
  const auto& targets = array.markers()[2];
  EXPECT_EQ(vertices.ns(), "vertices");
  EXPECT_EQ(vertices.type(), kSphereList);
  EXPECT_EQ(edges.ns(), "edges");
  EXPECT_EQ(edges.type(), kLineList);
  EXPECT_EQ(targets.ns(), "pois");
  EXPECT_EQ(targets.type(), kPoints);
  for (const auto& m : array.markers()) {
    EXPECT_EQ(m.header().frame_id(), "world");
    EXPECT_EQ(m.header().stamp().sec(), 1'700'000'000);
    EXPECT_EQ(m.header().stamp().nanosec(), 250'000'000u);
    EXPECT_EQ(m.action(), kAdd);
    EXPECT_EQ(m.id(), 0) << "each sample replaces the last";
    EXPECT_EQ(m.pose().orientation().w(), 1.0) << "a unit quaternion, which RViz2 asks for";
    EXPECT_GT(m.scale().x(), 0.0);
    EXPECT_EQ(m.lifetime().sec(), 0) << "forever";
  }
  ASSERT_EQ(vertices.points().size(), 3u);
  EXPECT_EQ(vertices.points()[2].x(), 10.0);
  EXPECT_EQ(vertices.points()[2].y(), 5.0);
  EXPECT_EQ(vertices.points()[2].z(), 2.0);
  ASSERT_EQ(edges.points().size(), 4u) << "two points an edge";
  EXPECT_EQ(edges.points()[2].x(), 10.0);
  EXPECT_EQ(edges.points()[3].y(), 5.0);
  ASSERT_EQ(targets.points().size(), 3u);
  ASSERT_EQ(targets.colors().size(), 3u);
  EXPECT_GT(targets.colors()[1].g(), 0.5f) << "POI 1 is seen: green";
  EXPECT_GT(targets.colors()[0].r(), 0.5f) << "POI 0 is seen by no vertex: red";
  EXPECT_LT(targets.colors()[0].g(), 0.5f);
  EXPECT_GT(targets.colors()[2].r(), 0.5f);
}

TEST(Ros2Markers, AnEmptyRoadmapIsThreeEmptyMarkersAndAClearIsOneDeleteAll) {
  const MarkerArray empty = roadmap_markers(Roadmap(0), {}, "map", kStamp);
  ASSERT_EQ(empty.markers().size(), 3u);
  for (const auto& m : empty.markers()) {
    EXPECT_TRUE(m.points().empty());
    EXPECT_GT(m.scale().x(), 0.0) << "sized from a unit extent";
  }
  const MarkerArray cleared = cleared_markers("map", kStamp);
  ASSERT_EQ(cleared.markers().size(), 1u);
  EXPECT_EQ(cleared.markers()[0].action(), kDeleteAll);
}

TEST(Ros2Markers, ATourIsAPathThroughItsStops) {
  const std::vector<Vec3> stops{{0, 0, 0}, {1, 2, 3}, {0, 0, 0}};
  const Path path = tour_path(stops, "map", kStamp);
  EXPECT_EQ(path.header().frame_id(), "map");
  ASSERT_EQ(path.poses().size(), 3u);
  EXPECT_EQ(path.poses()[1].pose().position().y(), 2.0);
  EXPECT_EQ(path.poses()[1].pose().orientation().w(), 1.0);
  EXPECT_EQ(path.poses()[1].header().frame_id(), "map");
  EXPECT_TRUE(tour_path({}, "map", kStamp).poses().empty());
}

}  // namespace
}  // namespace ispars::ros2
