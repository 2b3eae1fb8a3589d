#include "ispars/roadmap/roadmap.hpp"

#include <algorithm>
#include <utility>

namespace ispars {

Roadmap::Roadmap(std::size_t poi_count) : visible_(poi_count) {}

VertexId Roadmap::add_vertex(const Vec3& position, std::span<const PoiId> visible) {
  const auto id = static_cast<VertexId>(positions_.size());
  positions_.push_back(position);
  visible_.append(visible);
  adjacency_.emplace_back();
  parent_.push_back(id);
  size_.push_back(1);
  ++components_;
  log_.push_back({RoadmapChange::Kind::vertex, id});
  return id;
}

bool Roadmap::has_edge(VertexId u, VertexId v) const {
  const auto& shorter = adjacency_[u].size() <= adjacency_[v].size() ? adjacency_[u] : adjacency_[v];
  const VertexId other = adjacency_[u].size() <= adjacency_[v].size() ? v : u;
  return std::any_of(shorter.begin(), shorter.end(), [&](const Neighbor& n) { return n.vertex == other; });
}

bool Roadmap::add_edge(VertexId u, VertexId v) {
  if (u == v || has_edge(u, v)) return false;
  const double cost = (positions_[u] - positions_[v]).norm();
  adjacency_[u].push_back({v, cost});
  adjacency_[v].push_back({u, cost});
  log_.push_back({RoadmapChange::Kind::edge, static_cast<std::uint32_t>(edges_.size())});
  edges_.push_back({u, v, cost});

  // Union by size, path halving.
  auto find = [&](VertexId x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  };
  VertexId a = find(u);
  VertexId b = find(v);
  if (a != b) {
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    --components_;
  }
  return true;
}

VertexId Roadmap::component(VertexId v) const {
  while (parent_[v] != v) v = parent_[v];
  return v;
}

std::span<const RoadmapChange> Roadmap::changes_since(std::uint64_t version) const {
  if (version >= log_.size()) return {};
  return std::span<const RoadmapChange>(log_).subspan(static_cast<std::size_t>(version));
}

std::size_t Roadmap::covered_pois() const {
  std::vector<std::uint64_t> cover(visible_.words(), 0);
  for (std::size_t v = 0; v < vertex_count(); ++v) unite(cover, visible_.row(v));
  return count(cover);
}

std::size_t Roadmap::covered_pois_in_component_of(VertexId root) const {
  if (root >= vertex_count()) return 0;
  std::vector<std::uint64_t> cover(visible_.words(), 0);
  const VertexId c = component(root);
  for (VertexId v = 0; v < vertex_count(); ++v) {
    if (component(v) == c) unite(cover, visible_.row(v));
  }
  return count(cover);
}

}  // namespace ispars
