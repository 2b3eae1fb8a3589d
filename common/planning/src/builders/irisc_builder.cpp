#include "ispars/planning/builders/irisc_builder.hpp"

namespace ispars::planning {

IriscBuilder::IriscBuilder(const Scene& scene, const BuildOptions& options)
    : scene_(&scene),
      options_(options),
      rng_(options.seed),
      eta_(scene.config().dense_delta),
      radius_(scene.config().sparse_delta),
      graph_(scene.pois().size()),
      grid_(scene.config().sparse_delta),
      coverage_(poi_words(scene.pois().size()), 0) {
  scene.visible_pois(scene.config().root, visible_);
  const VertexId root = graph_.add_vertex(scene.config().root, visible_);
  grid_.insert(root, scene.config().root);
  unite(coverage_, graph_.visible(root));
}

void IriscBuilder::extend(std::size_t samples) {
  for (std::size_t i = 0; i < samples; ++i) {
    step(rng_.uniform_in(scene_->config().bounds));
    ++samples_;
  }
}

VertexId IriscBuilder::nearest(const Vec3& q) const {
  // A scan of the contiguous positions: the tree holds a fraction of N vertices, and a scan
  // never degrades with the distance to the sample the way a grid search does.
  VertexId best = 0;
  double best_d2 = INFINITY;
  const auto positions = graph_.positions();
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const double d2 = (positions[v] - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<VertexId>(v);
    }
  }
  return best;
}

void IriscBuilder::step(const Vec3& sample) {
  const VertexId from = nearest(sample);
  const Vec3& origin = graph_.position(from);
  const Vec3 towards = sample - origin;
  const double length = towards.norm();
  const Vec3 q = length <= eta_ ? sample : Vec3(origin + towards * (eta_ / length));
  if (!scene_->point_valid(q) || !scene_->segment_valid(origin, q)) return;

  scene_->visible_pois(q, visible_);
  std::vector<std::uint64_t> seen(coverage_.size(), 0);
  for (const PoiId id : visible_) seen[id / 64] |= std::uint64_t{1} << (id % 64);
  const bool informative = has_outside(seen, coverage_);
  if (!informative && !(rng_.uniform01() < options_.p_accept)) return;

  grid_.within(q, radius_, graph_.positions(), near_);
  const VertexId id = graph_.add_vertex(q, visible_);
  grid_.insert(id, q);
  unite(coverage_, graph_.visible(id));
  for (const auto& [distance, other] : near_) {
    if (other == from || scene_->segment_valid(graph_.position(other), q)) graph_.add_edge(other, id);
  }
  graph_.add_edge(from, id);  // the steering segment, already checked (a no-op when joined above)
}

}  // namespace ispars::planning
