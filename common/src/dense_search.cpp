#include "ispars/dense_search.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace ispars {

void DenseSearch::start(std::size_t vertex_count, VertexId source) {
  for (const VertexId v : touched_) {
    distance_[v] = INFINITY;
    parent_[v] = kNoVertex;
  }
  touched_.clear();
  heap_.clear();
  if (distance_.size() < vertex_count) {
    distance_.resize(vertex_count, INFINITY);
    parent_.resize(vertex_count, kNoVertex);
  }
  distance_[source] = 0.0;
  touched_.push_back(source);
  heap_.emplace_back(0.0, source);
}

std::pair<double, VertexId> DenseSearch::settle_next(const Roadmap& graph, double bound) {
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
      if (nd < distance_[n.vertex] && nd < bound) {
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

std::vector<VertexId> DenseSearch::path_to(VertexId source, VertexId target) const {
  std::vector<VertexId> path{target};
  while (path.back() != source) path.push_back(parent_[path.back()]);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace ispars
