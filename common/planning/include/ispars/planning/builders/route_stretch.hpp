#pragma once
// Route quality between the sparse roadmap's viewpoints. Theorem 1's proof joins consecutive
// sparse viewpoints x, x' of a tour and would need d_s(x, x') <= t d_C(x, x') between them (its
// "sparse-endpoint refinement"). The rules prove it only for near pairs (docs/sparse-stretch.md);
// this measures it for every pair: for pairs of sparse vertices that see a POI, the shortest
// sparse route against the shortest dense route between the same two samples, and against the
// straight segment where it is valid, binned by |x - x'| in units of Delta.

#include <cstddef>
#include <span>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// Ratios d_s / reference over the pairs of one bin. A pair the sparse roadmap does not join
/// counts as an infinite ratio (it is in `disconnected` and in every quantile).
struct StretchStats {
  std::size_t pairs = 0;
  std::size_t disconnected = 0;
  double median = 0.0;
  double p95 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
  double share_over_t = 0.0;  ///< Share of pairs with d_s > t * reference.
  /// max over the pairs of (d_s - t * reference) / Delta: the least c with d_s <= t reference +
  /// c Delta for every pair of the bin (negative when every pair is within t; infinite when a
  /// pair is not joined).
  double max_excess = 0.0;
};

/// Pairs whose endpoints are `from` <= |x - x'| / Delta < `to` apart.
struct StretchBin {
  double from = 0.0;
  double to = 0.0;
  StretchStats vs_dense;    ///< Against the dense route (pairs joined in the dense roadmap).
  StretchStats vs_segment;  ///< Against |x - x'|, pairs whose segment is valid (below segment_bins Delta).
};

struct RouteStretchReport {
  std::size_t viewpoints = 0;  ///< Sparse vertices that see at least one POI.
  std::size_t sources = 0;     ///< Viewpoints whose pairs were measured.
  /// [k, k + 1) Delta for k < options.bins, then [bins, inf).
  std::vector<StretchBin> bins;
  StretchBin within_3_delta;  ///< [0, 3) Delta together.
  StretchBin beyond_3_delta;  ///< [3, inf) Delta together.
  StretchBin all;             ///< Every pair.
};

struct RouteStretchOptions {
  double big_delta = 0.0;  ///< Delta, the bin unit.
  double stretch = 1.05;   ///< t, for share_over_t and max_excess.
  /// Measure pairs from at most this many viewpoints (every k-th, deterministic); 0: all.
  std::size_t max_sources = 0;
  std::size_t bins = 10;          ///< Bins of one Delta up to this many Delta, then one to infinity.
  std::size_t segment_bins = 10;  ///< Segments are checked for pairs closer than this many Delta.
};

/// Measures every pair (x, x') of POI-seeing sparse vertices with x among the sources, joined
/// in the dense roadmap: one Dijkstra per source on each graph, so every ratio is exact.
/// `dense_ids[s]` is sparse vertex s's dense vertex. Segment checks go through `scene` (only for
/// pairs closer than options.segment_bins Delta).
[[nodiscard]] RouteStretchReport measure_route_stretch(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                                       std::span<const VertexId> dense_ids,
                                                       const RouteStretchOptions& options);

}  // namespace ispars::planning
