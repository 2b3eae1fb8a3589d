#pragma once
// The dense roadmap G_d: a delta-PRM, every valid sample joined to every vertex within delta.

#include <utility>
#include <vector>

#include "ispars/planning/geometry/point_grid.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// G_d with its neighbour index. Edges: every pair within delta (<= delta) whose segment is valid.
class DeltaPrm {
 public:
  DeltaPrm(const Scene& scene, double delta);
  /// The delta-PRM `graph` is (grown by insert() with the same delta), indexed anew.
  DeltaPrm(const Scene& scene, double delta, Roadmap graph);

  /// Inserts a valid configuration seeing `visible` and its edges; returns its vertex.
  VertexId insert(const Vec3& q, std::span<const PoiId> visible);
  /// (distance, id) of the dense vertices within `radius` of q, nearest first.
  void within(const Vec3& q, double radius, std::vector<std::pair<double, std::uint32_t>>& out) const {
    grid_.within(q, radius, graph_.positions(), out);
  }

  /// Uses `scene` from now on: this one's geometry with more POIs (Scene::with_more_pois), which
  /// the graph's vertices are then counted over (each sees none of the new ones until told).
  void use_scene(const Scene& scene);
  /// Dense vertex v sees `ids` too.
  void add_visible(VertexId v, std::span<const PoiId> ids) { graph_.add_visible(v, ids); }

  [[nodiscard]] const Roadmap& graph() const { return graph_; }
  [[nodiscard]] double delta() const { return delta_; }

 private:
  const Scene* scene_;
  double delta_;
  Roadmap graph_;
  PointGrid grid_;
  std::vector<std::pair<double, std::uint32_t>> near_;
};

}  // namespace ispars::planning
