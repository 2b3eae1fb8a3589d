#include "ispars/planning/builders/build_cost.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ispars/scene_files/random.hpp"

namespace ispars::planning {

double free_fraction(const Scene& scene, int probes) {
  const Aabb& box = scene.config().bounds;
  scene_files::Rng rng(0x5ca1ab1e);
  int free = 0;
  for (int i = 0; i < probes; ++i) {
    const Vec3 p(rng.uniform(box.min.x(), box.max.x()), rng.uniform(box.min.y(), box.max.y()),
                 rng.uniform(box.min.z(), box.max.z()));
    free += scene.point_valid(p) ? 1 : 0;
  }
  // One probe's worth more than seen, so a scene whose free space no probe hit is not taken as
  // empty (that would make every pair look distant).
  return std::min(1.0, (free + 1.0) / probes);
}

namespace {

// What one compaction fold of `vertices` and `edges` holds beside the roadmap (build_cost.hpp).
double fold_bytes(double vertices, double edges) { return vertices * kFoldBytesPerVertex + edges * kFoldBytesPerEdge; }

}  // namespace

BuildCost estimate_build_cost(const Scene& scene, const RoadmapRecipe& recipe, std::uint64_t samples,
                              double free_fraction) {
  const Vec3 side = scene.config().bounds.max - scene.config().bounds.min;
  const double box = std::max(1e-300, side.x() * side.y() * side.z());
  const double f = std::clamp(free_fraction, 1e-6, 1.0);
  const double valid_samples = static_cast<double>(samples) * f;
  BuildCost cost;
  if (recipe.method == BuildMethod::ispars2) {
    // No dense graph: the sparse roadmap alone. Measured at 50,000-100,000 samples on the water
    // tower, truss bridge and city: under 7% of the samples become vertices, and 0.7-1.2 edges
    // are added per sample (the witnessed pairs); both doubled here, and published once more.
    cost.vertices = std::min(valid_samples, 0.12 * valid_samples + 2000.0);
    cost.edges = 2.5 * valid_samples;
    cost.bytes = 2.0 * (cost.vertices * kBytesPerVertex + cost.edges * kBytesPerEdge);
    cost.peak_bytes = cost.bytes + fold_bytes(cost.vertices, cost.edges);
    return cost;
  }
  double radius = recipe.dense_delta;
  if (recipe.method == BuildMethod::irisc) {
    // A sample is admitted when it sees a POI no vertex sees yet (at most once per POI), else
    // with probability p_accept.
    cost.vertices = std::min(valid_samples, static_cast<double>(scene.pois().size()) +
                                                std::clamp(recipe.p_accept, 0.0, 1.0) * valid_samples);
    radius = recipe.sparse_delta;
  } else {
    cost.vertices = valid_samples;
  }
  const double ball = 4.0 / 3.0 * std::numbers::pi * radius * radius * radius;
  const double pair_probability = std::min(1.0, ball / (box * f));
  cost.edges = cost.vertices * std::max(0.0, cost.vertices - 1.0) / 2.0 * pair_probability;
  // Dense and IRIS-C publish the roadmap itself to readers: a second copy. The sparse roadmaps
  // of spars and ispars are small beside their dense pair (a tenth is generous).
  const double copies = recipe.method == BuildMethod::dense || recipe.method == BuildMethod::irisc ? 2.0 : 1.1;
  cost.bytes = copies * (cost.vertices * kBytesPerVertex + cost.edges * kBytesPerEdge);
  // The store holds the sparse roadmap of a dense pair beside the dense one (a tenth, as above).
  const double stored = has_dense_pair(recipe.method) ? 1.1 : 1.0;
  cost.peak_bytes = cost.bytes + stored * fold_bytes(cost.vertices, cost.edges);
  return cost;
}

}  // namespace ispars::planning
