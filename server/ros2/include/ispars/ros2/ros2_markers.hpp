#pragma once
// What a ROS 2 viewer is shown of a roadmap and a tour, as the ROS 2 messages themselves
// (idl/ros2.idl): a roadmap is one visualization_msgs/MarkerArray of three markers, each replacing
// its previous sample (ns "vertices": a SPHERE_LIST of every vertex; "edges": a LINE_LIST, two
// points per edge; "pois": POINTS, green where some vertex sees the POI, red elsewhere), and a
// tour one nav_msgs/Path of its flown stops. Pure functions: no DDS entity is made here.

#include <chrono>
#include <span>
#include <string>

#include "ispars/roadmap/roadmap.hpp"
#include "ros2.h"

namespace ispars::ros2 {

/// The marker array a ROS 2 type is registered under, and the path.
using MarkerArray = visualization_msgs::msg::dds_::MarkerArray_;
using Path = nav_msgs::msg::dds_::Path_;

/// Marker types and actions (visualization_msgs/Marker's constants).
inline constexpr int kLineList = 5;
inline constexpr int kSphereList = 7;
inline constexpr int kPoints = 8;
inline constexpr int kAdd = 0;
inline constexpr int kDeleteAll = 3;

/// The ROS name token a scene's topics are under: its name with every character outside
/// A-Z a-z 0-9 _ made '_', runs of '_' made one, none at either end, and "scene_" before a
/// leading digit (ROS 2's rules for a name token). Distinct scenes may share one (the mirror
/// refuses the second).
[[nodiscard]] std::string ros_token(const std::string& scene);
/// The DDS topic of the scene's roadmap markers, "rt/ispars/<token>/roadmap" (ROS name
/// /ispars/<token>/roadmap), and of its last tour, ".../tour".
[[nodiscard]] std::string roadmap_topic(const std::string& token);
[[nodiscard]] std::string tour_topic(const std::string& token);

/// The markers of `roadmap`, whose POIs are at `pois` (the scene's, then its tasks'; a POI
/// beyond `pois` is not drawn), in `frame`, stamped `stamp`.
[[nodiscard]] MarkerArray roadmap_markers(const Roadmap& roadmap, std::span<const Vec3> pois, const std::string& frame,
                                          std::chrono::system_clock::time_point stamp);
/// One DELETEALL marker: a viewer drops what it drew of the scene (dropped or unloaded).
[[nodiscard]] MarkerArray cleared_markers(const std::string& frame, std::chrono::system_clock::time_point stamp);
/// The path through `stops` (a closed tour lists the root again at its end), in `frame`.
[[nodiscard]] Path tour_path(std::span<const Vec3> stops, const std::string& frame,
                             std::chrono::system_clock::time_point stamp);

}  // namespace ispars::ros2
