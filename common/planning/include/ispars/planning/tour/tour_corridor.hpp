#pragma once
// Corridor densification: the graph a flown tour is searched again on. Where a small roadmap
// loses to a dense one is where its viewpoints are, not how it routes between them; so around
// the tour it already flies (a tube of radius r around its straight segments) the corridor adds
// samples (fresh draws at a chosen density, the dense pair's vertices, or the build's stream drawn
// again) and joins each, within a sparse edge's reach, to its nearest vertices by checked segments. The roadmap itself
// is left untouched: the corridor lives in the tour's own graph, a copy of the roadmap's graph with the tube's vertices
// after it.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// Where a corridor's samples come from.
enum class CorridorSource : std::uint8_t {
  fresh,    ///< Uniform draws over the tube at `density` per cubic metre, from Rng(seed).
  samples,  ///< The given `samples` that lie in the tube, in their order (Inspection-SPARS's dense pair).
  /// The build's samples drawn again: `stream_count` uniform draws in the scene's bounds from
  /// Rng(stream_seed), as the builders draw them, kept when they lie in the tube (ispars2, which
  /// keeps no dense graph).
  stream,
};

/// How a corridor is drawn and joined.
struct CorridorOptions {
  CorridorSource source = CorridorSource::fresh;
  double radius = 0.0;       ///< r: the tube's radius around the flown path (> 0).
  double join_radius = 0.0;  ///< Vertices this close are joined by a checked segment (> 0).
  /// Samples per cubic metre of tube (>= 0), uniform over the tube (the union of the capsules
  /// around the segments); the valid ones are kept.
  double density = 0.0;
  /// At most this many fresh draws (the density is lowered to fit), or tube samples kept from
  /// `samples` or the stream (the first ones, in their order).
  std::size_t max_samples = 20'000;
  std::span<const Vec3> samples;   ///< With CorridorSource::samples.
  std::uint64_t stream_seed = 0;   ///< With CorridorSource::stream: the build's seed
  std::uint64_t stream_count = 0;  ///< and its sample count.
  /// Each new vertex is joined to at most this many vertices, its nearest within join_radius
  /// (bounds the corridor's edges and checks to max_joins per vertex; 0: no bound).
  std::size_t max_joins = 0;
  std::uint64_t seed = 1;  ///< The draws' stream: the same input gives the same graph.
  /// When set and true, no more samples are drawn or joined (the graph so far is returned, still
  /// sound: `stopped` says so).
  const std::atomic<bool>* stop = nullptr;
  /// When > 0, drawing and joining end as `stop` ends them once this many seconds have passed.
  double budget_seconds = 0.0;
};

/// The tour's own graph: the base graph's vertices and edges (same ids), then one vertex per
/// flown stop that is not a base vertex, then the tube's valid samples; each flown segment is an
/// edge, and each new vertex is joined to every vertex within join_radius whose segment is valid.
struct CorridorGraph {
  InspectionGraph graph;
  std::vector<Vec3> positions;  ///< Of every vertex of `graph`.
  std::vector<VertexId> walk;   ///< The flown path as a closed walk of `graph`, from vertex 0.
  std::size_t samples = 0;      ///< Tube samples added (valid, and not a base vertex's position).
  std::size_t draws = 0;        ///< Tube samples drawn, or found in the tube.
  std::size_t segments_checked = 0;
  bool stopped = false;  ///< `stop` ended the joins early.
};

/// The corridor around the flown path `stops` (closed: front == back == base vertex 0's
/// position). `stop_vertices[i]` is stop i's vertex in `base` (kNoVertex when it is none, as a
/// refined stop's); `base_positions` places base's vertices. Each stop's and sample's chi comes
/// from `scene`, whose POI ids must be base's. Throws std::invalid_argument on mismatched sizes
/// or a radius that is not positive.
[[nodiscard]] CorridorGraph corridor_graph(const Scene& scene, const InspectionGraph& base,
                                           std::span<const Vec3> base_positions, std::span<const Vec3> stops,
                                           std::span<const VertexId> stop_vertices, const CorridorOptions& options);

}  // namespace ispars::planning
