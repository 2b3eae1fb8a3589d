#include "ispars/planning/builders/delta_prm.hpp"

namespace ispars::planning {

DeltaPrm::DeltaPrm(const Scene& scene, double delta)
    : scene_(&scene), delta_(delta), graph_(scene.pois().size()), grid_(delta) {}

DeltaPrm::DeltaPrm(const Scene& scene, double delta, Roadmap graph)
    : scene_(&scene), delta_(delta), graph_(std::move(graph)), grid_(delta) {
  for (VertexId v = 0; v < graph_.vertex_count(); ++v) grid_.insert(v, graph_.position(v));
}

VertexId DeltaPrm::insert(const Vec3& q, std::span<const PoiId> visible) {
  grid_.within(q, delta_, graph_.positions(), near_);
  const VertexId id = graph_.add_vertex(q, visible);
  grid_.insert(id, q);
  for (const auto& [distance, other] : near_) {
    if (scene_->segment_valid(graph_.position(other), q)) graph_.add_edge(other, id);
  }
  return id;
}

void DeltaPrm::use_scene(const Scene& scene) {
  scene_ = &scene;
  graph_.widen_pois(scene.pois().size());
}

}  // namespace ispars::planning
