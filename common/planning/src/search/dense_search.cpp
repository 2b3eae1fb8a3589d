#include "ispars/planning/search/dense_search.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace ispars::planning {

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

std::vector<VertexId> DenseSearch::path_to(VertexId source, VertexId target) const {
  std::vector<VertexId> path{target};
  while (path.back() != source) path.push_back(parent_[path.back()]);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace ispars::planning
