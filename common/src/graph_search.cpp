#include "ispars/graph_search.hpp"

#include <cmath>
#include <functional>
#include <queue>
#include <utility>

namespace ispars {

std::vector<double> shortest_distances(const Roadmap& graph, VertexId source) {
  std::vector<double> distance(graph.vertex_count(), INFINITY);
  using Entry = std::pair<double, VertexId>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  distance[source] = 0.0;
  open.emplace(0.0, source);
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > distance[u]) continue;
    for (const Neighbor& n : graph.neighbors(u)) {
      const double nd = d + n.cost;
      if (nd < distance[n.vertex]) {
        distance[n.vertex] = nd;
        open.emplace(nd, n.vertex);
      }
    }
  }
  return distance;
}

}  // namespace ispars
