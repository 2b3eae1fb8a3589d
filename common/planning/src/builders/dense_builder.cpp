#include "ispars/planning/builders/dense_builder.hpp"

#include <algorithm>

namespace ispars::planning {

DenseBuilder::DenseBuilder(const Scene& scene, const BuildOptions& options)
    : scene_(&scene), options_(options), rng_(options.seed), prm_(scene, scene.config().dense_delta) {
  prm_.insert(scene.config().root, scene.visibility().visible_pois(scene.config().root));
}

DenseBuilder::DenseBuilder(const Scene& scene, const BuildOptions& options, Roadmap roadmap, std::size_t samples)
    : scene_(&scene),
      options_(options),
      rng_(options.seed),
      prm_(scene, scene.config().dense_delta, std::move(roadmap)) {
  skip_samples(rng_, samples);
  samples_ = samples;
}

void DenseBuilder::extend(std::size_t samples) {
  while (samples > 0) {
    const std::size_t n = std::min<std::size_t>(samples, 256);
    prepare_samples(*scene_, rng_, n, options_.threads, batch_);
    for (const PreparedSample& s : batch_) {
      if (s.valid) prm_.insert(s.q, s.visible);
    }
    samples -= n;
    samples_ += n;
  }
}

void DenseBuilder::step(const Vec3& sample) {
  if (scene_->point_valid(sample)) prm_.insert(sample, scene_->visibility().visible_pois(sample));
}

}  // namespace ispars::planning
