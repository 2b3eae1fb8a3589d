#include "ispars/planning/builders/sample_batch.hpp"

#include <algorithm>
#include <thread>

namespace ispars::planning {

void prepare_samples(const Scene& scene, scene_files::Rng& rng, std::size_t count, unsigned threads,
                     std::vector<PreparedSample>& out) {
  out.resize(count);
  for (auto& sample : out) sample.q = rng.uniform_in(scene.config().bounds);
  const auto prepare = [&](std::size_t first, std::size_t stride) {
    for (std::size_t i = first; i < count; i += stride) {
      PreparedSample& s = out[i];
      s.valid = scene.point_valid(s.q);
      if (s.valid) {
        scene.visible_pois(s.q, s.visible);
      } else {
        s.visible.clear();
      }
    }
  };
  const std::size_t workers = std::clamp<std::size_t>(threads, 1, std::max<std::size_t>(1, count / 16));
  if (workers <= 1) {
    prepare(0, 1);
    return;
  }
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(prepare, t, workers);
  prepare(0, workers);
  for (auto& th : pool) th.join();
}

void skip_samples(scene_files::Rng& rng, std::size_t count) {
  rng.discard(3 * static_cast<std::uint64_t>(count));  // uniform_in: one draw a coordinate
}

}  // namespace ispars::planning
