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
  edges_before_.push_back(static_cast<std::uint32_t>(edges_.size()));
  parent_.push_back(id);
  size_.push_back(1);
  ++components_;
  return id;
}

bool Roadmap::has_edge(VertexId u, VertexId v) const {
  const auto& shorter = adjacency_[u].size() <= adjacency_[v].size() ? adjacency_[u] : adjacency_[v];
  const VertexId other = adjacency_[u].size() <= adjacency_[v].size() ? v : u;
  return std::find(shorter.begin(), shorter.end(), other) != shorter.end();
}

bool Roadmap::add_edge(VertexId u, VertexId v) {
  if (u == v || has_edge(u, v)) return false;
  add_new_edge(u, v);
  return true;
}

void Roadmap::add_new_edge(VertexId u, VertexId v) {
  adjacency_[u].push_back(v);
  adjacency_[v].push_back(u);
  edges_.push_back({u, v});

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
}

VertexId Roadmap::component(VertexId v) const {
  while (parent_[v] != v) v = parent_[v];
  return v;
}

VertexId Roadmap::first_vertex_at_or_after(std::uint64_t i) const {
  VertexId lo = 0;
  auto hi = static_cast<VertexId>(positions_.size());
  while (lo < hi) {  // positions v + edges_before_[v] rise strictly with v
    const VertexId mid = lo + (hi - lo) / 2;
    if (mid + std::uint64_t{edges_before_[mid]} < i) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  return lo;
}

bool Roadmap::same_changes_as(const Roadmap& other) const {
  const auto same_edges = [&] {
    return std::equal(edges_.begin(), edges_.end(), other.edges_.begin(), other.edges_.end(),
                      [](const EdgeEnds& a, const EdgeEnds& b) { return a.u == b.u && a.v == b.v; });
  };
  return positions_ == other.positions_ && visible_ == other.visible_ && edges_before_ == other.edges_before_ &&
         same_edges();
}

RoadmapChange Roadmap::change(std::uint64_t i) const {
  RoadmapChange out;
  for_each_change(i, i + 1, [&](const RoadmapChange& c) { out = c; });
  return out;
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
