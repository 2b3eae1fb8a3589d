#pragma once
// An incremental Dijkstra over a growing graph whose arrays are reused from one search to the
// next: only the vertices a search touched are reset, so a small local search costs little
// however large the graph has grown.

#include <algorithm>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// Settles vertices one at a time in order of (distance, id) from a source.
class DenseSearch {
 public:
  /// Starts a new search from `source` over a graph of `vertex_count` vertices.
  void start(std::size_t vertex_count, VertexId source);
  /// Settles the next vertex if its distance is below `bound`; returns (distance, vertex), or
  /// (infinity, kNoVertex) when nothing below the bound is left.
  std::pair<double, VertexId> settle_next(const Roadmap& graph, double bound) {
    return settle_next(graph, bound, [](VertexId, double) { return true; });
  }
  /// The same, reaching a neighbour v at tentative distance d only when keep(v, d) holds: a
  /// goal-directed search passes a keep() that is true on every prefix of the paths it wants.
  template <class Keep>
  std::pair<double, VertexId> settle_next(const Roadmap& graph, double bound, Keep&& keep);
  /// The distance found to v: exact once v is settled, infinity when the search never reached it.
  [[nodiscard]] double distance(VertexId v) const { return v < distance_.size() ? distance_[v] : INFINITY; }
  /// Every vertex this search reached (its distance finite: the length of a route to it), the
  /// source included.
  [[nodiscard]] const std::vector<VertexId>& reached() const { return touched_; }
  /// The settled path from the source to `target`, both included.
  [[nodiscard]] std::vector<VertexId> path_to(VertexId source, VertexId target) const;

 private:
  std::vector<double> distance_;
  std::vector<VertexId> parent_;
  std::vector<VertexId> touched_;
  std::vector<std::pair<double, VertexId>> heap_;  // min-heap on (distance, id)
};

template <class Keep>
std::pair<double, VertexId> DenseSearch::settle_next(const Roadmap& graph, double bound, Keep&& keep) {
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<>());
    const auto [d, u] = heap_.back();
    heap_.pop_back();
    if (d > distance_[u]) continue;  // stale entry
    if (!(d < bound)) {
      heap_.clear();
      return {INFINITY, kNoVertex};
    }
    for (const Neighbor& n : graph.neighbors(u)) {
      const double nd = d + n.cost;
      if (nd < distance_[n.vertex] && nd < bound && keep(n.vertex, nd)) {
        if (std::isinf(distance_[n.vertex])) touched_.push_back(n.vertex);
        distance_[n.vertex] = nd;
        parent_[n.vertex] = u;
        heap_.emplace_back(nd, n.vertex);
        std::push_heap(heap_.begin(), heap_.end(), std::greater<>());
      }
    }
    return {d, u};
  }
  return {INFINITY, kNoVertex};
}

}  // namespace ispars::planning
