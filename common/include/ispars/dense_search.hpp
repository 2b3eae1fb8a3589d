#pragma once
// An incremental Dijkstra over a growing graph whose arrays are reused from one search to the
// next: only the vertices a search touched are reset, so a small local search costs little
// however large the graph has grown.

#include <utility>
#include <vector>

#include "ispars/roadmap.hpp"

namespace ispars {

/// Settles vertices one at a time in order of (distance, id) from a source.
class DenseSearch {
 public:
  /// Starts a new search from `source` over a graph of `vertex_count` vertices.
  void start(std::size_t vertex_count, VertexId source);
  /// Settles the next vertex if its distance is below `bound`; returns (distance, vertex), or
  /// (infinity, kNoVertex) when nothing below the bound is left.
  std::pair<double, VertexId> settle_next(const Roadmap& graph, double bound);
  /// The settled path from the source to `target`, both included.
  [[nodiscard]] std::vector<VertexId> path_to(VertexId source, VertexId target) const;

 private:
  std::vector<double> distance_;
  std::vector<VertexId> parent_;
  std::vector<VertexId> touched_;
  std::vector<std::pair<double, VertexId>> heap_;  // min-heap on (distance, id)
};

}  // namespace ispars
