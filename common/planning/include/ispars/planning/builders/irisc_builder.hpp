#pragma once
// The IRIS-C baseline: the coverage-informed RRG of IRIS (Fu, Salzman, Alterovitz 2021).

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/geometry/point_grid.hpp"

namespace ispars::planning {

/// RRG with step eta = delta and connection radius r_RRG = Delta: steer from the nearest
/// vertex toward a uniform sample by at most eta; a valid new state that sees a POI the roadmap
/// does not yet see is always admitted, any other with probability p_accept. An admitted state
/// joins every vertex within r_RRG in view.
class IriscBuilder final : public RoadmapBuilder {
 public:
  IriscBuilder(const Scene& scene, const BuildOptions& options);
  void extend(std::size_t samples) override;
  /// One RRG iteration steering toward `sample`.
  void step(const Vec3& sample) override;
  [[nodiscard]] const Roadmap& roadmap() const override { return graph_; }

 private:
  VertexId nearest(const Vec3& q) const;

  const Scene* scene_;
  BuildOptions options_;
  scene_files::Rng rng_;
  double eta_;
  double radius_;
  Roadmap graph_;
  PointGrid grid_;
  std::vector<std::uint64_t> coverage_;
  std::vector<PoiId> visible_;
  std::vector<std::pair<double, std::uint32_t>> near_;
};

}  // namespace ispars::planning
