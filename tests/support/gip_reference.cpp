#include "support/gip_reference.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

#include "ispars/scene_files/random.hpp"

namespace ispars::test {

// A random connected geometric graph: n points in the unit cube, each joined to its k nearest,
// plus a chain so it is connected; each vertex sees a few of `pois` POIs.
InspectionGraph random_instance(std::uint64_t seed, std::size_t n, std::size_t pois, std::size_t nearest) {
  scene_files::Rng rng(seed);
  std::vector<Vec3> p(n);
  for (auto& x : p) x = Vec3(rng.uniform01(), rng.uniform01(), rng.uniform01());
  std::vector<RoadmapEdge> edges;
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<std::pair<double, std::size_t>> near;
    for (std::size_t j = 0; j < n; ++j) {
      if (j != i) near.push_back({(p[i] - p[j]).norm(), j});
    }
    std::sort(near.begin(), near.end());
    for (std::size_t k = 0; k < std::min(nearest, near.size()); ++k) {
      edges.push_back({static_cast<VertexId>(i), static_cast<VertexId>(near[k].second), near[k].first});
    }
    if (i > 0) edges.push_back({static_cast<VertexId>(i - 1), static_cast<VertexId>(i), (p[i] - p[i - 1]).norm()});
  }
  std::vector<std::vector<PoiId>> visible(n);
  for (std::size_t v = 1; v < n; ++v) {
    const auto count = static_cast<std::size_t>(rng.uniform01() * 3.0);
    for (std::size_t k = 0; k < count; ++k) visible[v].push_back(static_cast<PoiId>(rng.uniform01() * pois) % pois);
  }
  for (PoiId q = 0; q < pois; ++q) {  // every POI seen somewhere
    visible[1 + static_cast<std::size_t>(rng.uniform01() * (n - 1)) % (n - 1)].push_back(q);
  }
  return InspectionGraph::from_edges(n, edges, std::move(visible), pois);
}

// Exact optimum: shortest paths between all vertices, then Dijkstra over (vertex, seen set).
double exact_optimum(const InspectionGraph& g, std::size_t pois) {
  const std::size_t n = g.vertex_count();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<std::vector<double>> d(n, std::vector<double>(n, inf));
  for (std::size_t s = 0; s < n; ++s) {
    d[s][s] = 0;
    using Item = std::pair<double, VertexId>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    open.push({0.0, static_cast<VertexId>(s)});
    while (!open.empty()) {
      const auto [dist, v] = open.top();
      open.pop();
      if (dist > d[s][v]) continue;
      for (const Neighbor& nb : g.neighbors(v)) {
        if (dist + nb.cost < d[s][nb.vertex]) {
          d[s][nb.vertex] = dist + nb.cost;
          open.push({d[s][nb.vertex], nb.vertex});
        }
      }
    }
  }
  std::vector<std::uint32_t> mask(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    for (const PoiId q : g.visible(static_cast<VertexId>(v))) mask[v] |= 1u << q;
  }
  const std::uint32_t full = (1u << pois) - 1;
  std::vector<double> best((full + 1) * n, inf);
  using State = std::pair<double, std::pair<std::uint32_t, std::size_t>>;
  std::priority_queue<State, std::vector<State>, std::greater<>> open;
  best[mask[0] * n + 0] = 0;
  open.push({0.0, {mask[0], 0}});
  double answer = inf;
  while (!open.empty()) {
    const auto [cost, key] = open.top();
    open.pop();
    const auto [m, v] = key;
    if (cost > best[m * n + v]) continue;
    if (m == full) answer = std::min(answer, cost + d[v][0]);
    for (std::size_t u = 0; u < n; ++u) {
      const std::uint32_t mu = m | mask[u];
      const double c = cost + d[v][u];
      if (c < best[mu * n + u]) {
        best[mu * n + u] = c;
        open.push({c, {mu, u}});
      }
    }
  }
  return answer;
}

}  // namespace ispars::test
