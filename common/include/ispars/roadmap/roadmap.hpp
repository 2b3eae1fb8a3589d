#pragma once
// A roadmap: vertices with their POI sets, undirected weighted edges, connected components, and
// an ordered change log that a consumer can replay from any version.

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "ispars/roadmap/poi_set.hpp"
#include "ispars/geometry/vec.hpp"

namespace ispars {

using VertexId = std::uint32_t;
inline constexpr VertexId kNoVertex = std::numeric_limits<VertexId>::max();

/// An undirected edge; cost is the Euclidean length of its segment.
struct RoadmapEdge {
  VertexId u = 0;
  VertexId v = 0;
  double cost = 0.0;
};

/// One entry of the change log. The entry at position i has version i + 1.
struct RoadmapChange {
  enum class Kind : std::uint8_t { vertex, edge };
  Kind kind = Kind::vertex;
  std::uint32_t index = 0;  ///< Vertex id or edge index.
};

/// A neighbour in the adjacency list.
struct Neighbor {
  VertexId vertex = 0;
  double cost = 0.0;
};

/// Vertices (positions laid out contiguously, chi as bitsets), edges, components (union-find)
/// and the change log. Only grows. Const methods are safe from many threads while no one writes.
class Roadmap {
 public:
  explicit Roadmap(std::size_t poi_count = 0);

  /// Adds a vertex seeing `visible`; returns its id (ids are dense: 0, 1, 2, ...).
  VertexId add_vertex(const Vec3& position, std::span<const PoiId> visible);
  /// Adds the edge u-v with cost |u - v|, unless it exists or u == v; returns whether it was added.
  bool add_edge(VertexId u, VertexId v);

  [[nodiscard]] std::size_t vertex_count() const { return positions_.size(); }
  [[nodiscard]] std::size_t edge_count() const { return edges_.size(); }
  [[nodiscard]] const Vec3& position(VertexId v) const { return positions_[v]; }
  [[nodiscard]] std::span<const Vec3> positions() const { return positions_; }
  [[nodiscard]] PoiBits visible(VertexId v) const { return visible_.row(v); }
  [[nodiscard]] const PoiSetTable& visibility_table() const { return visible_; }
  [[nodiscard]] std::span<const Neighbor> neighbors(VertexId v) const { return adjacency_[v]; }
  [[nodiscard]] std::span<const RoadmapEdge> edges() const { return edges_; }
  [[nodiscard]] bool has_edge(VertexId u, VertexId v) const;

  /// Representative of v's connected component (stable only until the next edge).
  [[nodiscard]] VertexId component(VertexId v) const;
  [[nodiscard]] bool same_component(VertexId u, VertexId v) const { return component(u) == component(v); }
  /// Number of connected components.
  [[nodiscard]] std::size_t component_count() const { return components_; }

  /// The version after the latest change (0 for an empty roadmap).
  [[nodiscard]] std::uint64_t version() const { return log_.size(); }
  /// Every change after `version`, in order; entry k has version `version + k + 1`.
  [[nodiscard]] std::span<const RoadmapChange> changes_since(std::uint64_t version) const;

  /// POIs seen by some vertex, and by some vertex in the component of `root`.
  [[nodiscard]] std::size_t covered_pois() const;
  [[nodiscard]] std::size_t covered_pois_in_component_of(VertexId root) const;

 private:
  std::vector<Vec3> positions_;
  PoiSetTable visible_;
  std::vector<std::vector<Neighbor>> adjacency_;
  std::vector<RoadmapEdge> edges_;
  std::vector<RoadmapChange> log_;
  std::vector<VertexId> parent_;  // union-find, by size, with path halving on writes
  std::vector<std::uint32_t> size_;
  std::size_t components_ = 0;
};

}  // namespace ispars
