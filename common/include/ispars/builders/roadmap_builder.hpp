#pragma once
// Incremental roadmap construction: Dense (delta-PRM), SPARS, Inspection-SPARS and IRIS-C.

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/roadmap.hpp"
#include "ispars/scene/scene.hpp"

namespace ispars {

/// Settings of a build that are not scene parameters.
struct BuildOptions {
  std::uint64_t seed = 1;
  /// Threads for the per-sample work that does not depend on the roadmap (point check, chi).
  /// Any count gives the same roadmap.
  unsigned threads = 1;
  /// IRIS-C: probability of admitting a state that adds no new POI (the paper's 0.2).
  double p_accept = 0.2;
  /// spars and ispars: which rule set grows the sparse roadmap.
  SparsVariant variant = SparsVariant::stretch;
  /// spars, ispars and ispars2, stretch rules: the additive slack of the join and witnessed-pair
  /// bounds as a fraction of Delta, in [0, 1]: a route is long past t d + stretch_slack Delta.
  /// 0 keeps the bounds purely multiplicative; a positive slack lets the roadmap converge.
  double stretch_slack = 0.0;
  /// The slack applies from this sample of the build's stream on (0: from the first); the samples
  /// before it see purely multiplicative bounds, so a build's first stretch_slack_after samples
  /// grow exactly the roadmap that no slack grows, and a long extend then converges.
  std::uint64_t stretch_slack_after = 0;
  /// The stretch rules' cache of routes between sparse vertices (KnownRoutes): at most this many
  /// pairs, 16-32 bytes each (2048 .. 2^30). Any size gives the same roadmap; a small one
  /// searches more often.
  std::size_t known_route_pairs = std::size_t{1} << 22;
};

/// A roadmap under construction. extend(a) then extend(b) gives exactly the roadmap that
/// extend(a + b) gives: the samples come from one seeded stream.
class RoadmapBuilder {
 public:
  virtual ~RoadmapBuilder() = default;

  /// Draws and processes `samples` more samples (a sample may be invalid and be dropped).
  virtual void extend(std::size_t samples) = 0;
  /// Processes one given sample of the sampling box (not drawn from the builder's stream, and
  /// not counted in samples()). Invalid samples are dropped.
  virtual void step(const Vec3& sample) = 0;
  /// The method's roadmap: the sparse one for spars and ispars. Vertex 0 is the root.
  [[nodiscard]] virtual const Roadmap& roadmap() const = 0;
  /// The paired dense roadmap (spars and ispars), else nullptr.
  [[nodiscard]] virtual const Roadmap* dense() const { return nullptr; }
  /// For each vertex of roadmap(), the same sample's vertex in dense() (spars, ispars).
  [[nodiscard]] virtual std::span<const VertexId> dense_ids() const { return {}; }

  /// Samples drawn so far.
  [[nodiscard]] std::size_t samples() const { return samples_; }

 protected:
  std::size_t samples_ = 0;
};

/// A builder for `method` over `scene` (which must outlive it), holding just the root.
[[nodiscard]] std::unique_ptr<RoadmapBuilder> make_roadmap_builder(BuildMethod method, const Scene& scene,
                                                                   const BuildOptions& options);

/// Whether a builder of `method` can go on from its roadmap alone (resume_roadmap_builder):
/// dense and ispars2. The others keep more than their roadmap (the dense pair's
/// representatives and supports, IRIS-C's draws) and are rebuilt by replaying their samples.
[[nodiscard]] bool resumes_from_roadmap(BuildMethod method);

/// A builder for `method` that goes on from `roadmap`, which make_roadmap_builder(method, scene,
/// options) grew in `samples` samples, without drawing them again: extending it gives byte for
/// byte what extending the uninterrupted builder gives. Throws std::invalid_argument when
/// resumes_from_roadmap(method) is false or the roadmap has no root.
[[nodiscard]] std::unique_ptr<RoadmapBuilder> resume_roadmap_builder(BuildMethod method, const Scene& scene,
                                                                     const BuildOptions& options, Roadmap roadmap,
                                                                     std::size_t samples);

}  // namespace ispars
