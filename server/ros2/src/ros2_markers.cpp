#include "ispars/ros2/ros2_markers.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <vector>

namespace ispars::ros2 {
namespace {

using Marker = visualization_msgs::msg::dds_::Marker_;
using Color = std_msgs::msg::dds_::ColorRGBA_;
using Header = std_msgs::msg::dds_::Header_;
using Point = geometry_msgs::msg::dds_::Point_;

Header header_of(const std::string& frame, std::chrono::system_clock::time_point stamp) {
  const auto since = stamp.time_since_epoch();
  const auto seconds = std::chrono::duration_cast<std::chrono::seconds>(since);
  Header h;
  h.stamp().sec(static_cast<std::int32_t>(seconds.count()));
  h.stamp().nanosec(
      static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(since - seconds).count()));
  h.frame_id(frame);
  return h;
}

Color color(float r, float g, float b, float a = 1.0f) {
  Color c;
  c.r(r);
  c.g(g);
  c.b(b);
  c.a(a);
  return c;
}

Point point(const Vec3& v) {
  Point p;
  p.x(v.x());
  p.y(v.y());
  p.z(v.z());
  return p;
}

// A marker of `type` in namespace `ns` (id 0: each sample replaces the last), unit pose.
Marker marker(const Header& header, const char* ns, int type, double size, const Color& c) {
  Marker m;
  m.header(header);
  m.ns(ns);
  m.id(0);
  m.type(type);
  m.action(kAdd);
  m.pose().orientation().w(1.0);
  m.scale().x(size);
  m.scale().y(size);
  m.scale().z(size);
  m.color(c);
  return m;
}

// The diagonal of the box around the vertices and POIs (1 when there are none): what the
// markers' sizes scale with, so a bridge and a tank are drawn alike.
double extent(const Roadmap& roadmap, std::span<const Vec3> pois) {
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const Vec3& p : roadmap.positions()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const Vec3& p : pois) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double diagonal = (hi - lo).norm();
  return lo.x() <= hi.x() && diagonal > 0.0 ? diagonal : 1.0;
}

std::vector<bool> seen_pois(const Roadmap& roadmap) {
  std::vector<bool> seen(roadmap.poi_count(), false);
  const PoiSetTable& table = roadmap.visibility_table();
  std::vector<std::uint64_t> cover(table.words(), 0);
  for (std::size_t v = 0; v < roadmap.vertex_count(); ++v) {
    const PoiBits row = table.row(v);
    for (std::size_t w = 0; w < row.size(); ++w) cover[w] |= row[w];
  }
  for (std::size_t i = 0; i < seen.size(); ++i) seen[i] = (cover[i / 64] >> (i % 64)) & 1u;
  return seen;
}

}  // namespace

std::string ros_token(const std::string& scene) {
  std::string token;
  for (const char c : scene) {
    const bool kept = std::isalnum(static_cast<unsigned char>(c)) != 0;
    if (kept) {
      token += c;
    } else if (!token.empty() && token.back() != '_') {
      token += '_';
    }
  }
  while (!token.empty() && token.back() == '_') token.pop_back();
  if (token.empty() || std::isdigit(static_cast<unsigned char>(token.front())) != 0) token = "scene_" + token;
  while (token.back() == '_') token.pop_back();
  return token;
}

std::string roadmap_topic(const std::string& token) { return "rt/ispars/" + token + "/roadmap"; }
std::string tour_topic(const std::string& token) { return "rt/ispars/" + token + "/tour"; }

MarkerArray roadmap_markers(const Roadmap& roadmap, std::span<const Vec3> pois, const std::string& frame,
                            std::chrono::system_clock::time_point stamp) {
  const Header header = header_of(frame, stamp);
  const double size = extent(roadmap, pois);
  Marker vertices = marker(header, "vertices", kSphereList, size / 300.0, color(0.2f, 0.45f, 1.0f));
  vertices.points().reserve(roadmap.vertex_count());
  for (const Vec3& p : roadmap.positions()) vertices.points().push_back(point(p));
  Marker edges = marker(header, "edges", kLineList, size / 1500.0, color(0.6f, 0.6f, 0.65f, 0.8f));
  edges.points().reserve(2 * roadmap.edge_count());
  for (const EdgeEnds& e : roadmap.edge_ends()) {
    edges.points().push_back(point(roadmap.position(e.u)));
    edges.points().push_back(point(roadmap.position(e.v)));
  }
  Marker targets = marker(header, "pois", kPoints, size / 250.0, color(1.0f, 1.0f, 1.0f));
  const std::vector<bool> seen = seen_pois(roadmap);
  const std::size_t drawn = std::min(pois.size(), seen.size());
  targets.points().reserve(drawn);
  targets.colors().reserve(drawn);
  for (std::size_t i = 0; i < drawn; ++i) {
    targets.points().push_back(point(pois[i]));
    targets.colors().push_back(seen[i] ? color(0.1f, 0.85f, 0.25f) : color(0.95f, 0.15f, 0.1f));
  }
  MarkerArray out;
  out.markers() = {std::move(vertices), std::move(edges), std::move(targets)};
  return out;
}

MarkerArray cleared_markers(const std::string& frame, std::chrono::system_clock::time_point stamp) {
  Marker clear;
  clear.header(header_of(frame, stamp));
  clear.action(kDeleteAll);
  clear.pose().orientation().w(1.0);
  MarkerArray out;
  out.markers().push_back(std::move(clear));
  return out;
}

Path tour_path(std::span<const Vec3> stops, const std::string& frame, std::chrono::system_clock::time_point stamp) {
  Path path;
  path.header(header_of(frame, stamp));
  path.poses().reserve(stops.size());
  for (const Vec3& s : stops) {
    geometry_msgs::msg::dds_::PoseStamped_ pose;
    pose.header(path.header());
    pose.pose().position(point(s));
    pose.pose().orientation().w(1.0);
    path.poses().push_back(std::move(pose));
  }
  return path;
}

}  // namespace ispars::ros2
