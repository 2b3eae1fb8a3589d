#pragma once
// A roadmap: vertices with their POI sets, undirected edges, connected components, and an
// ordered change log that a consumer can replay from any version.
//
// Laid out for graphs of tens of millions of edges (the dense delta-PRM): an edge is stored once
// as its two ends and once in each end's neighbour list, 16 bytes in all. Its cost is not stored:
// it is the Euclidean length of the segment, computed from the positions when asked for, and
// bit-identical to the length computed when the edge was added. The change log is not stored
// either: the edge count when each vertex was added places every vertex and edge in it.

#include <algorithm>
#include <cstdint>
#include <iterator>
#include <limits>
#include <span>
#include <vector>

#include "ispars/roadmap/poi_set.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars {

using VertexId = std::uint32_t;
inline constexpr VertexId kNoVertex = std::numeric_limits<VertexId>::max();

/// An undirected edge as stored: its two ends, in the order they were added.
struct EdgeEnds {
  VertexId u = 0;
  VertexId v = 0;
};

/// An undirected edge with its cost, the Euclidean length of its segment.
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

/// A neighbour with the cost of the edge to it.
struct Neighbor {
  VertexId vertex = 0;
  double cost = 0.0;
};

/// The neighbours of one vertex with their edge costs, computed as they are read.
class NeighborList {
 public:
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = Neighbor;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = Neighbor;
    iterator() = default;
    iterator(const VertexId* at, const Vec3* positions, const Vec3* from)
        : at_(at), positions_(positions), from_(from) {}
    Neighbor operator*() const { return {*at_, (*from_ - positions_[*at_]).norm()}; }
    iterator& operator++() {
      ++at_;
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++at_;
      return old;
    }
    bool operator==(const iterator& o) const { return at_ == o.at_; }

   private:
    const VertexId* at_ = nullptr;
    const Vec3* positions_ = nullptr;
    const Vec3* from_ = nullptr;
  };

  NeighborList(std::span<const VertexId> ids, const Vec3* positions, const Vec3* from)
      : ids_(ids), positions_(positions), from_(from) {}
  [[nodiscard]] iterator begin() const { return {ids_.data(), positions_, from_}; }
  [[nodiscard]] iterator end() const { return {ids_.data() + ids_.size(), positions_, from_}; }
  [[nodiscard]] std::size_t size() const { return ids_.size(); }
  [[nodiscard]] bool empty() const { return ids_.empty(); }

 private:
  std::span<const VertexId> ids_;
  const Vec3* positions_;
  const Vec3* from_;
};

class Roadmap;

/// Every edge of a roadmap with its cost, in the order added, computed as it is read.
class EdgeList {
 public:
  class iterator {
   public:
    using iterator_category = std::forward_iterator_tag;
    using value_type = RoadmapEdge;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = RoadmapEdge;
    iterator() = default;
    iterator(const EdgeList* list, std::size_t i) : list_(list), i_(i) {}
    RoadmapEdge operator*() const { return (*list_)[i_]; }
    iterator& operator++() {
      ++i_;
      return *this;
    }
    iterator operator++(int) {
      iterator old = *this;
      ++i_;
      return old;
    }
    bool operator==(const iterator& o) const { return i_ == o.i_; }

   private:
    const EdgeList* list_ = nullptr;
    std::size_t i_ = 0;
  };

  EdgeList(std::span<const EdgeEnds> ends, std::span<const Vec3> positions) : ends_(ends), positions_(positions) {}
  [[nodiscard]] RoadmapEdge operator[](std::size_t i) const {
    const EdgeEnds e = ends_[i];
    return {e.u, e.v, (positions_[e.u] - positions_[e.v]).norm()};
  }
  [[nodiscard]] iterator begin() const { return {this, 0}; }
  [[nodiscard]] iterator end() const { return {this, ends_.size()}; }
  [[nodiscard]] std::size_t size() const { return ends_.size(); }
  [[nodiscard]] bool empty() const { return ends_.empty(); }

 private:
  std::span<const EdgeEnds> ends_;
  std::span<const Vec3> positions_;
};

/// Vertices (positions laid out contiguously, chi as bitsets), edges, components (union-find)
/// and the change log. Only grows. Const methods are safe from many threads while no one writes.
class Roadmap {
 public:
  explicit Roadmap(std::size_t poi_count = 0);

  /// Adds a vertex seeing `visible`; returns its id (ids are dense: 0, 1, 2, ...).
  VertexId add_vertex(const Vec3& position, std::span<const PoiId> visible);
  /// Grows the POIs to `poi_count` (new POIs get the next ids and are seen by no vertex yet), for
  /// an inspection task added to a built roadmap. Neither this nor add_visible is a change of the
  /// log: version() stays. Throws std::invalid_argument when `poi_count` is below poi_count().
  void widen_pois(std::size_t poi_count) { visible_.widen(poi_count); }
  /// Vertex v sees `ids` too (each below poi_count(); throws std::out_of_range otherwise).
  void add_visible(VertexId v, std::span<const PoiId> ids) { visible_.add(v, ids); }
  [[nodiscard]] std::size_t poi_count() const { return visible_.poi_count(); }
  /// Adds the edge u-v with cost |u - v|, unless it exists or u == v; returns whether it was added.
  bool add_edge(VertexId u, VertexId v);
  /// Adds the edge u-v that the caller knows is new (u != v, both exist, no u-v yet): add_edge
  /// without its look through a neighbour list. For a batch checked whole (apply_checked_batch).
  void add_new_edge(VertexId u, VertexId v);
  /// Makes room for `extra` more neighbours of v and `edges` more edges, growing each array at
  /// least geometrically, so that adding a batch's edges moves each array at most once.
  void reserve_neighbors(VertexId v, std::size_t extra) { reserve_more(adjacency_[v], extra); }
  void reserve_edges(std::size_t extra) { reserve_more(edges_, extra); }

  [[nodiscard]] std::size_t vertex_count() const { return positions_.size(); }
  [[nodiscard]] std::size_t edge_count() const { return edges_.size(); }
  [[nodiscard]] const Vec3& position(VertexId v) const { return positions_[v]; }
  [[nodiscard]] std::span<const Vec3> positions() const { return positions_; }
  [[nodiscard]] PoiBits visible(VertexId v) const { return visible_.row(v); }
  [[nodiscard]] const PoiSetTable& visibility_table() const { return visible_; }
  /// The neighbours of v, in the order their edges were added.
  [[nodiscard]] std::span<const VertexId> neighbor_ids(VertexId v) const { return adjacency_[v]; }
  /// The neighbours of v with the cost of each edge.
  [[nodiscard]] NeighborList neighbors(VertexId v) const { return {adjacency_[v], positions_.data(), &positions_[v]}; }
  /// Edge i (in the order added) with its cost.
  [[nodiscard]] RoadmapEdge edge(std::size_t i) const { return edges()[i]; }
  /// Every edge with its cost, in the order added.
  [[nodiscard]] EdgeList edges() const { return {edges_, positions_}; }
  /// Every edge's two ends, in the order added.
  [[nodiscard]] std::span<const EdgeEnds> edge_ends() const { return edges_; }
  [[nodiscard]] bool has_edge(VertexId u, VertexId v) const;

  /// Representative of v's connected component (stable only until the next edge).
  [[nodiscard]] VertexId component(VertexId v) const;
  [[nodiscard]] bool same_component(VertexId u, VertexId v) const { return component(u) == component(v); }
  /// Number of connected components.
  [[nodiscard]] std::size_t component_count() const { return components_; }

  /// The version after the latest change (0 for an empty roadmap).
  [[nodiscard]] std::uint64_t version() const { return positions_.size() + edges_.size(); }
  /// The change whose version is `i + 1` (i < version()).
  [[nodiscard]] RoadmapChange change(std::uint64_t i) const;
  /// Calls f(RoadmapChange) for every change after version `from` up to and including version
  /// `to` (clamped to version()), in order.
  template <class F>
  void for_each_change(std::uint64_t from, std::uint64_t to, F&& f) const;

  /// The same vertices (positions and POIs) and edges, added in the same order: the same change
  /// log. Compares the stored arrays; encodes nothing.
  [[nodiscard]] bool same_changes_as(const Roadmap& other) const;

  /// POIs seen by some vertex, and by some vertex in the component of `root`.
  [[nodiscard]] std::size_t covered_pois() const;
  [[nodiscard]] std::size_t covered_pois_in_component_of(VertexId root) const;

 private:
  /// The first vertex whose change is at position `i` or later of the log.
  [[nodiscard]] VertexId first_vertex_at_or_after(std::uint64_t i) const;

  template <class T>
  static void reserve_more(std::vector<T>& v, std::size_t extra) {
    if (v.size() + extra > v.capacity()) v.reserve(std::max(v.size() + extra, 2 * v.capacity()));
  }

  std::vector<Vec3> positions_;
  PoiSetTable visible_;
  std::vector<std::vector<VertexId>> adjacency_;
  std::vector<EdgeEnds> edges_;
  std::vector<std::uint32_t> edges_before_;  // per vertex: the edge count when it was added
  std::vector<VertexId> parent_;             // union-find, by size, with path halving on writes
  std::vector<std::uint32_t> size_;
  std::size_t components_ = 0;
};

template <class F>
void Roadmap::for_each_change(std::uint64_t from, std::uint64_t to, F&& f) const {
  if (to > version()) to = version();
  // Vertex v's change is at position v + edges_before_[v]; every other position is an edge,
  // the (position - vertices before it)-th.
  VertexId v = first_vertex_at_or_after(from);
  for (std::uint64_t i = from; i < to; ++i) {
    if (v < positions_.size() && v + std::uint64_t{edges_before_[v]} == i) {
      f(RoadmapChange{RoadmapChange::Kind::vertex, v});
      ++v;
    } else {
      f(RoadmapChange{RoadmapChange::Kind::edge, static_cast<std::uint32_t>(i - v)});
    }
  }
}

}  // namespace ispars
