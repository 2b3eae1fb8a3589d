#pragma once
// Uniform samples of the sampling box with the work that depends on nothing but the sample
// itself (point check, chi), done for a whole batch on several threads.

#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {

/// One sample, checked and (when valid) with its visible POIs.
struct PreparedSample {
  Vec3 q = Vec3::Zero();
  bool valid = false;
  std::vector<PoiId> visible;
};

/// Draws `count` samples from rng (three uniforms each, in order) and prepares them on
/// `threads` threads. The result does not depend on the thread count.
void prepare_samples(const Scene& scene, scene_files::Rng& rng, std::size_t count, unsigned threads,
                     std::vector<PreparedSample>& out);

/// Advances rng past the draws prepare_samples makes for `count` samples, without making them:
/// where a builder resumed after `count` samples goes on drawing.
void skip_samples(scene_files::Rng& rng, std::size_t count);

}  // namespace ispars::planning
