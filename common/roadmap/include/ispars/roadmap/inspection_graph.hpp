#pragma once
// The graph inspection planning (GIP) input: an undirected weighted graph whose vertices see sets
// of POIs, with a root. Built from a roadmap, or read from IRIS text files.

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// A graph for tour planning: compressed adjacency, POI lists per vertex, vertex 0 is the root.
class InspectionGraph {
 public:
  /// From a roadmap (its vertex 0 is the root, as every builder makes it).
  static InspectionGraph from_roadmap(const Roadmap& roadmap);
  /// From IRIS files PREFIX_vertex and PREFIX_edge (see docs); edges with valid = 0 are kept only
  /// with `all_edges`. Throws InputError naming the file, the line and what is wrong.
  static InspectionGraph read_iris(const std::filesystem::path& prefix, bool all_edges);
  /// From an edge list and POI lists (for tests and tools). Throws InputError on an edge whose
  /// ends are out of range or whose cost is negative or not finite.
  static InspectionGraph from_edges(std::size_t vertices, std::span<const RoadmapEdge> edges,
                                    std::vector<std::vector<PoiId>> visible, std::size_t poi_count);

  [[nodiscard]] std::size_t vertex_count() const { return visible_.size(); }
  [[nodiscard]] std::size_t edge_count() const { return edges_.size(); }
  [[nodiscard]] std::size_t poi_count() const { return poi_count_; }
  [[nodiscard]] std::span<const Neighbor> neighbors(VertexId v) const {
    return {neighbors_.data() + offsets_[v], neighbors_.data() + offsets_[v + 1]};
  }
  [[nodiscard]] std::span<const PoiId> visible(VertexId v) const { return visible_[v]; }
  [[nodiscard]] std::span<const RoadmapEdge> edges() const { return edges_; }
  /// The cost of the cheapest edge u-v, or a negative number when there is none.
  [[nodiscard]] double edge_cost(VertexId u, VertexId v) const;
  /// Vertices reachable from v (v included), ascending.
  [[nodiscard]] std::vector<VertexId> component_of(VertexId v) const;

 private:
  void finish();
  std::size_t poi_count_ = 0;
  std::vector<RoadmapEdge> edges_;
  std::vector<std::vector<PoiId>> visible_;
  std::vector<std::size_t> offsets_;
  std::vector<Neighbor> neighbors_;
};

}  // namespace ispars
