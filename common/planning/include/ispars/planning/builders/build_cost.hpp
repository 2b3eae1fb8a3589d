#pragma once
// What a roadmap will hold before it is built: an upper estimate of its vertices, edges and
// memory from the scene's sampling box, its free fraction, the method and delta. The service
// refuses a build or extend whose estimate does not fit its memory budget, before any memory
// grows.

#include <cstdint>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/roadmap/build_recipe.hpp"

namespace ispars::planning {

/// An upper estimate of one roadmap's size.
struct BuildCost {
  double vertices = 0.0;  ///< Vertices of the largest graph the build keeps (the dense one for dense, spars, ispars).
  double edges = 0.0;     ///< Its edges.
  double bytes = 0.0;     ///< Memory held by the builder and the copies published to readers.
  /// `bytes` plus the most a store's compaction fold (or a restart's recovery) of this roadmap
  /// holds beside it: what the memory budget admits (ispars-bench peak measures it).
  double peak_bytes = 0.0;
};

/// Memory per vertex and per edge of a roadmap as built and held, rounded up from what a daemon
/// held for 98,101 dense vertices and 9,974,613 dense edges: 355 MiB with Inspection-SPARS,
/// 621 MiB with Dense and its published copy (docs/results/service.md), about 32 and 28 bytes
/// an edge beside 512 a vertex.
inline constexpr double kBytesPerVertex = 512.0;
inline constexpr double kBytesPerEdge = 40.0;

/// What a compaction fold of a stored roadmap holds at once, per stored vertex and edge, beside
/// the roadmap itself: the snapshot file read in and its payload, the journal's, the decoded
/// whole and its encoding (roadmap_store_compaction.cpp). Set from ispars-bench peak
/// (docs/results/service.md), rounded up.
inline constexpr double kFoldBytesPerVertex = 512.0;
inline constexpr double kFoldBytesPerEdge = 96.0;

/// The fraction of the sampling box whose points pass the point check, from `probes` probes of a
/// fixed seed (the same answer every time for one scene).
[[nodiscard]] double free_fraction(const Scene& scene, int probes = 2000);

/// The estimate for `samples` samples of `recipe` (its method, deltas and p_accept) on `scene`,
/// given its free fraction. Vertices: every valid sample (dense, spars, ispars), or for IRIS-C
/// one per POI plus p_accept of the rest. Edges: every pair of vertices within the connection
/// radius (dense_delta; Delta for IRIS-C), as if obstacles cut none and the ball never left the box.
/// ispars2 keeps no dense graph: a measured bound on its sparse roadmap (build_cost.cpp).
[[nodiscard]] BuildCost estimate_build_cost(const Scene& scene, const RoadmapRecipe& recipe, std::uint64_t samples,
                                            double free_fraction);

}  // namespace ispars::planning
