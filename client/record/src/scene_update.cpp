#include "ispars/record/scene_update.hpp"

#include <chrono>

namespace ispars::record {
namespace {

using nlohmann::json;

json stamp(std::uint64_t ns) { return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}}; }
json vec(const Vec3& p) { return {{"x", p.x()}, {"y", p.y()}, {"z", p.z()}}; }
json color(double r, double g, double b, double a = 1.0) { return {{"r", r}, {"g", g}, {"b", b}, {"a", a}}; }
json unit_pose(const Vec3& at = Vec3::Zero()) {
  return {{"position", vec(at)}, {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", 0.0}, {"w", 1.0}}}};
}

// An entity with every field the schema requires, its primitives empty.
json entity(const std::string& id, const SceneStyle& style, std::uint64_t ns) {
  return {{"timestamp", stamp(ns)},
          {"frame_id", style.frame},
          {"id", id},
          {"lifetime", {{"sec", 0}, {"nsec", 0}}},
          {"frame_locked", false},
          {"metadata", json::array()},
          {"arrows", json::array()},
          {"cubes", json::array()},
          {"spheres", json::array()},
          {"cylinders", json::array()},
          {"lines", json::array()},
          {"triangles", json::array()},
          {"texts", json::array()},
          {"models", json::array()}};
}

json line(int type, json points, double thickness, const json& c) {
  return {{"type", type},
          {"pose", unit_pose()},
          {"thickness", thickness},
          {"scale_invariant", true},
          {"points", std::move(points)},
          {"color", c},
          {"colors", json::array()},
          {"indices", json::array()}};
}

}  // namespace

std::uint64_t now_ns() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

const std::string& scene_update_schema() {
  static const std::string schema =
#include "foxglove_scene_update_schema.inc"
      ;
  return schema;
}

json roadmap_update(const Roadmap& roadmap, std::size_t first_vertex, std::size_t first_edge, const std::string& id,
                    bool clear, const SceneStyle& style, std::uint64_t time_ns) {
  json e = entity(id, style, time_ns);
  const json vertex_color = color(0.2, 0.45, 1.0);
  for (std::size_t v = first_vertex; v < roadmap.vertex_count(); ++v) {
    const double s = style.vertex_size;
    e["spheres"].push_back({{"pose", unit_pose(roadmap.position(static_cast<VertexId>(v)))},
                            {"size", {{"x", s}, {"y", s}, {"z", s}}},
                            {"color", vertex_color}});
  }
  json points = json::array();
  for (std::size_t k = first_edge; k < roadmap.edge_count(); ++k) {
    const EdgeEnds ends = roadmap.edge_ends()[k];
    points.push_back(vec(roadmap.position(ends.u)));
    points.push_back(vec(roadmap.position(ends.v)));
  }
  if (!points.empty())
    e["lines"].push_back(line(2, std::move(points), style.edge_thickness, color(0.6, 0.6, 0.65, 0.8)));
  json deletions = json::array();
  if (clear) deletions.push_back({{"timestamp", stamp(time_ns)}, {"type", 1}, {"id", ""}});  // ALL
  return {{"deletions", std::move(deletions)}, {"entities", json::array({std::move(e)})}};
}

json tour_update(std::span<const Vec3> stops, const SceneStyle& style, std::uint64_t time_ns) {
  json e = entity("tour", style, time_ns);
  json points = json::array();
  for (const Vec3& s : stops) points.push_back(vec(s));
  e["lines"].push_back(line(0, std::move(points), 3.0 * style.edge_thickness, color(1.0, 0.55, 0.0)));
  return {{"deletions", json::array()}, {"entities", json::array({std::move(e)})}};
}

double vertex_size_for(const Roadmap& roadmap) {
  if (roadmap.vertex_count() < 2) return 0.1;
  Vec3 lo = roadmap.position(0), hi = lo;
  for (const Vec3& p : roadmap.positions()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double d = (hi - lo).norm();
  return d > 0.0 ? d / 300.0 : 0.1;
}

}  // namespace ispars::record
