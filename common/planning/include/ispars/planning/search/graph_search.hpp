#pragma once
// Shortest paths: the one Dijkstra of the planning library, over any graph that lists its
// neighbours as `Neighbor` spans (Roadmap, InspectionGraph).

#include <functional>
#include <limits>
#include <queue>
#include <span>
#include <utility>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// A start of a search: a vertex and the cost of reaching it.
struct SearchSource {
  VertexId vertex = 0;
  double cost = 0.0;
};

/// Dijkstra from `sources` over `graph` (anything with vertex_count() and neighbors(v)).
/// `distance` gets every vertex's shortest distance (infinity when unreached) and, when given,
/// `parent` its predecessor (kNoVertex for sources and unreached vertices). `settled(v)` is
/// called as each vertex is settled, in order of distance; returning true ends the search
/// there (later vertices keep tentative or infinite distances).
template <class Graph, class Settled>
void dijkstra(const Graph& graph, std::span<const SearchSource> sources, std::vector<double>& distance,
              std::vector<VertexId>* parent, Settled&& settled) {
  distance.assign(graph.vertex_count(), std::numeric_limits<double>::infinity());
  if (parent != nullptr) parent->assign(graph.vertex_count(), kNoVertex);
  using Item = std::pair<double, VertexId>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  for (const SearchSource& s : sources) {
    if (s.cost < distance[s.vertex]) {
      distance[s.vertex] = s.cost;
      open.push({s.cost, s.vertex});
    }
  }
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > distance[v]) continue;
    if (settled(v)) return;
    for (const Neighbor& n : graph.neighbors(v)) {
      const double nd = d + n.cost;
      if (nd < distance[n.vertex]) {
        distance[n.vertex] = nd;
        if (parent != nullptr) (*parent)[n.vertex] = v;
        open.push({nd, n.vertex});
      }
    }
  }
}

/// Dijkstra from `sources` to every vertex (no early end).
template <class Graph>
void dijkstra(const Graph& graph, std::span<const SearchSource> sources, std::vector<double>& distance,
              std::vector<VertexId>* parent = nullptr) {
  dijkstra(graph, sources, distance, parent, [](VertexId) { return false; });
}

/// Dijkstra from `source`: the length of a shortest path to every vertex (infinity when
/// unreachable).
[[nodiscard]] std::vector<double> shortest_distances(const Roadmap& graph, VertexId source);

}  // namespace ispars::planning
