#pragma once
// Incremental roadmap construction: Dense (delta-PRM), SPARS, Inspection-SPARS and IRIS-C.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

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
  /// 0 keeps the bounds purely multiplicative; a positive slack thins the repairs out, so a long
  /// build grows far more slowly (measured, not proven: docs/results/ispars2.md).
  double stretch_slack = 0.0;
  /// The slack applies from this sample of the build's stream on (0: from the first); the samples
  /// before it see purely multiplicative bounds, so a build's first stretch_slack_after samples
  /// grow exactly the roadmap that no slack grows, and a long extend then grows slowly.
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
  /// Adds an inspection task: `widened` is this builder's scene with POIs appended
  /// (Scene::with_more_pois), used from now on (it must outlive the builder). The vertices built
  /// learn which new POIs they see, and the method does what it promises for them too; returns
  /// the vertices added. Throws std::invalid_argument when `widened` does not begin with this
  /// scene's POIs, or the method cannot take POIs without a rebuild; AdditionStopped
  /// (poi_visibility.hpp) when `keep_going` said no part way (the builder must then be discarded).
  virtual std::size_t add_pois(const Scene& widened, const std::function<bool()>& keep_going = {});

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

/// A builder's roadmaps after `samples` samples of its stream, as a store gives them back: what
/// resume_roadmap_builder goes on from.
struct BuiltRoadmaps {
  std::uint64_t samples = 0;
  Roadmap roadmap;                  ///< The method's roadmap (the sparse one for spars and ispars).
  std::optional<Roadmap> dense;     ///< The dense pair's G_d (spars and ispars), else none.
  std::vector<VertexId> dense_ids;  ///< For each vertex of `roadmap`, its vertex in `dense`.
};

/// Whether a builder of `method` takes new POIs into its built roadmap (add_pois): spars, ispars
/// and ispars2. The others need a rebuild with the POIs in the scene.
[[nodiscard]] bool takes_pois(BuildMethod method);

/// Whether a builder of `method` can go on from its roadmap alone: dense and ispars2.
[[nodiscard]] bool resumes_from_roadmap(BuildMethod method);

/// Whether a builder of `method` can go on from its roadmaps (BuiltRoadmaps) without drawing its
/// samples again: all but IRIS-C, whose admissions drew from the stream in a way its roadmap
/// does not record, and which is rebuilt by replaying its samples.
[[nodiscard]] bool resumes_without_replay(BuildMethod method);

/// A builder for `method` that goes on from `built`, which make_roadmap_builder(method, scene,
/// options) grew in built.samples samples, without drawing them again: extending it gives byte
/// for byte what extending the uninterrupted builder gives. The dense pair (spars, ispars) needs
/// `dense` and `dense_ids`; dense and ispars2 need neither. Throws std::invalid_argument when
/// resumes_without_replay(method) is false, when the roadmaps do not start with the scene's root,
/// or when the dense pair's roadmaps do not fit each other.
[[nodiscard]] std::unique_ptr<RoadmapBuilder> resume_roadmap_builder(BuildMethod method, const Scene& scene,
                                                                     const BuildOptions& options, BuiltRoadmaps built);

}  // namespace ispars::planning
