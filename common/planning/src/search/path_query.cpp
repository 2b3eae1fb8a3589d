#include "ispars/planning/search/path_query.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/search/graph_search.hpp"

namespace ispars::planning {
namespace {

struct Join {
  VertexId vertex = kNoVertex;
  double cost = 0.0;
};

// Every roadmap vertex within `radius` of p reachable by a free segment, nearest first.
std::vector<Join> joins(const Scene& scene, const Roadmap& roadmap, const Vec3& p, double radius, const char* field) {
  if (!p.allFinite()) throw params::InputError("path", field, "must be three finite numbers");
  if (!scene.config().bounds.contains(p)) {
    throw params::InputError("path", field,
                             fmt::format("[{}, {}, {}] is outside the scene bounds", p.x(), p.y(), p.z()));
  }
  if (!scene.point_valid(p)) {
    throw params::InputError("path", field, fmt::format("[{}, {}, {}] is in collision", p.x(), p.y(), p.z()));
  }
  std::vector<Join> near;
  const auto positions = roadmap.positions();
  for (VertexId v = 0; v < positions.size(); ++v) {
    const double d = (positions[v] - p).norm();
    if (d <= radius) near.push_back({v, d});
  }
  std::sort(near.begin(), near.end(),
            [](const Join& a, const Join& b) { return a.cost < b.cost || (a.cost == b.cost && a.vertex < b.vertex); });
  std::vector<Join> free;
  for (const Join& j : near) {
    if (scene.segment_valid(p, positions[j.vertex])) free.push_back(j);
  }
  if (free.empty()) {
    throw params::InputError("path", field,
                             fmt::format("[{}, {}, {}] has no free segment to a roadmap vertex within Delta = {} "
                                         "({} vertices within it)",
                                         p.x(), p.y(), p.z(), radius, near.size()));
  }
  return free;
}

}  // namespace

RoadmapPath plan_path(const Scene& scene, const Roadmap& roadmap, const Vec3& start, const Vec3& goal,
                      double join_radius) {
  const std::vector<Join> from = joins(scene, roadmap, start, join_radius, "from");
  const std::vector<Join> to = joins(scene, roadmap, goal, join_radius, "to");

  RoadmapPath path;
  // Straight through, when the two points see each other.
  const double direct = (goal - start).norm();
  // Dijkstra from every start join at once (the joins' costs as starting distances).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<SearchSource> sources;
  sources.reserve(from.size());
  for (const Join& j : from) sources.push_back({j.vertex, j.cost});
  std::vector<double> dist;
  std::vector<VertexId> parent;
  dijkstra(roadmap, sources, dist, &parent);
  VertexId best = kNoVertex;
  double best_cost = inf;
  for (const Join& j : to) {
    const double c = dist[j.vertex] + j.cost;
    if (c < best_cost) {
      best_cost = c;
      best = j.vertex;
    }
  }
  if (direct <= join_radius && scene.segment_valid(start, goal) && direct <= best_cost) {
    path.waypoints = {start, goal};
    path.length = direct;
    return path;
  }
  if (best == kNoVertex) {
    throw params::InputError(
        "path", "to", "the goal joins the roadmap in a different component from the start: no path on this roadmap");
  }
  for (VertexId v = best; v != kNoVertex; v = parent[v]) path.vertices.push_back(v);
  std::reverse(path.vertices.begin(), path.vertices.end());
  path.waypoints.push_back(start);
  for (const VertexId v : path.vertices) path.waypoints.push_back(roadmap.position(v));
  path.waypoints.push_back(goal);
  for (std::size_t i = 1; i < path.waypoints.size(); ++i) {
    path.length += (path.waypoints[i] - path.waypoints[i - 1]).norm();
  }
  return path;
}

}  // namespace ispars::planning
