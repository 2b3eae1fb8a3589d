#pragma once
// The paper's "Dense" baseline: the delta-PRM alone.

#include "ispars/planning/builders/delta_prm.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/sample_batch.hpp"

namespace ispars::planning {

/// Every valid sample joins the roadmap with an edge to every vertex within delta in view.
class DenseBuilder final : public RoadmapBuilder {
 public:
  DenseBuilder(const Scene& scene, const BuildOptions& options);
  /// The builder that grew `roadmap` in `samples` samples, resumed: its roadmap and its place in
  /// the sample stream are its whole state. resume_roadmap_builder checks the roadmap's root.
  DenseBuilder(const Scene& scene, const BuildOptions& options, Roadmap roadmap, std::size_t samples);
  void extend(std::size_t samples) override;
  void step(const Vec3& sample) override;
  [[nodiscard]] const Roadmap& roadmap() const override { return prm_.graph(); }

 private:
  const Scene* scene_;
  BuildOptions options_;
  scene_files::Rng rng_;
  DeltaPrm prm_;
  std::vector<PreparedSample> batch_;
};

}  // namespace ispars::planning
