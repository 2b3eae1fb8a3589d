#pragma once
// Route quality between the sparse roadmap's viewpoints. Theorem 1's proof joins consecutive
// sparse viewpoints x, x' of a tour and needs d_s(x, x') <= t d_C(x, x') between them (its
// "sparse-endpoint refinement"). This measures that directly: for pairs of sparse vertices that
// see a POI, the shortest sparse route against the shortest dense route between the same two
// samples, and against the straight segment where it is valid, binned by |x - x'|.

#include <array>
#include <cstddef>
#include <span>

#include "ispars/roadmap/roadmap.hpp"
#include "ispars/scene/scene.hpp"

namespace ispars {

/// Ratios d_s / reference over the pairs of one bin. A pair the sparse roadmap does not join
/// counts as an infinite ratio (it is in `disconnected` and in every quantile).
struct StretchStats {
  std::size_t pairs = 0;
  std::size_t disconnected = 0;
  double median = 0.0;
  double p95 = 0.0;
  double max = 0.0;
  double share_over_t = 0.0;  ///< Share of pairs with d_s > t * reference.
};

/// Pairs whose endpoints are `from` <= |x - x'| / Delta < `to` apart.
struct StretchBin {
  double from = 0.0;
  double to = 0.0;
  StretchStats vs_dense;    ///< Against the dense route (pairs joined in the dense roadmap).
  StretchStats vs_segment;  ///< Against |x - x'|, pairs whose segment is valid (bins below 3 Delta).
};

struct RouteStretchReport {
  std::size_t viewpoints = 0;  ///< Sparse vertices that see at least one POI.
  std::size_t sources = 0;     ///< Viewpoints whose pairs were measured.
  /// [0, 1), [1, 2), [2, 3) and [3, inf) Delta.
  std::array<StretchBin, 4> bins;
  StretchBin within_3_delta;   ///< [0, 3) Delta together.
};

struct RouteStretchOptions {
  double big_delta = 0.0;  ///< Delta, the bin unit.
  double stretch = 1.05;   ///< t, for share_over_t.
  /// Measure pairs from at most this many viewpoints (every k-th, deterministic); 0: all.
  std::size_t max_sources = 0;
};

/// Measures every pair (x, x') of POI-seeing sparse vertices with x among the sources, joined
/// in the dense roadmap. `dense_ids[s]` is sparse vertex s's dense vertex. Segment checks go
/// through `scene` (only for pairs closer than 3 Delta).
[[nodiscard]] RouteStretchReport measure_route_stretch(const Scene& scene, const Roadmap& sparse, const Roadmap& dense,
                                                       std::span<const VertexId> dense_ids,
                                                       const RouteStretchOptions& options);

}  // namespace ispars
