#pragma once
// Shortest paths on a roadmap.

#include <vector>

#include "ispars/roadmap.hpp"

namespace ispars {

/// Dijkstra from `source`: the length of a shortest path to every vertex (infinity when
/// unreachable).
[[nodiscard]] std::vector<double> shortest_distances(const Roadmap& graph, VertexId source);

}  // namespace ispars
