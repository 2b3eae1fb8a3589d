#include "ispars/planning/search/graph_search.hpp"

namespace ispars::planning {

std::vector<double> shortest_distances(const Roadmap& graph, VertexId source) {
  std::vector<double> distance;
  const SearchSource from{source, 0.0};
  dijkstra(graph, std::span<const SearchSource>(&from, 1), distance);
  return distance;
}

}  // namespace ispars::planning
