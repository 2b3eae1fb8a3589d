#pragma once
// The tour a drone flies, from a small roadmap: the one tour pipeline of the daemon's TOUR,
// `ispars-lab tour`, the Python package and the viewer.
//
//   1. search the roadmap's graph (gip_solver.hpp) and shortcut the walk (tour_shortcut.hpp);
//   2. corridor densification (tour_corridor.hpp): samples in a tube around the flown tour,
//      joined within a sparse edge's reach, searched again from the incumbent (so never worse),
//      repeated while a round pays and the budget lasts;
//   3. viewpoint refinement and 2-opt on the stops (viewpoint_refinement.hpp);
//   4. the independent check (flown_tour_check.hpp).
//
// The roadmap is never changed: the corridor lives in the tour's own graph. Every stage keeps
// the path closed, collision-free and seeing every target, and none lengthens it.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/tour/flown_tour_check.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_corridor.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "ispars/planning/tour/viewpoint_refinement.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// The pipeline's settings. `search` is the roadmap search's: its root must be 0, its stop ends
/// every stage, and its budget_seconds is the whole pipeline's wall-clock budget. With
/// search.max_iterations > 0 every search (the roadmap's and each corridor's) runs that many
/// iterations per thread (equal work, deterministic) under that budget; with 0 the budget is
/// shared: half to the roadmap search, the rest among the rounds (in each, most to the corridor).
struct FlownTourOptions {
  GipOptions search;
  /// Rounds at most of a corridor then refinement (0: refinement alone, once); a round that gains
  /// under 0.1% ends them.
  std::size_t rounds = 3;
  /// Where the tube's samples come from: fresh draws at the density below; the dense pair's
  /// vertices (`corridor_samples`); or the build's stream drawn again (build_seed, build_samples).
  CorridorSource corridor_source = CorridorSource::fresh;
  std::span<const Vec3> corridor_samples;
  std::uint64_t build_seed = 0;  ///< With CorridorSource::stream.
  double corridor_radius = 0.0;  ///< r: the tube's radius; 0: Delta / 2 (the scene's sparse_delta / 2).
  double join_radius = 0.0;      ///< 0: 2 Delta, a sparse edge's reach.
  /// Tube samples per cubic metre; 0: `density_factor` times the build's (build_samples over the
  /// sampling box's volume).
  double corridor_density = 0.0;
  double density_factor = 4.0;
  /// N of the roadmap's build (fresh with corridor_density 0, or the stream's length; 0: no corridor).
  std::uint64_t build_samples = 0;
  std::size_t corridor_max_samples = 20'000;  ///< Tube samples per round at most.
  /// Each tube sample is joined to at most this many vertices, its nearest within join_radius
  /// (0: every one): bounds the corridor's edges and segment checks.
  std::size_t corridor_max_joins = 24;
  /// With search.max_iterations > 0: each corridor search's iterations per thread (at most the
  /// roadmap search's). It starts from the incumbent, so it needs far fewer.
  std::uint64_t corridor_iterations = 500;
  bool refine = true;  ///< Viewpoint refinement and 2-opt.
  /// Its draws and passes (its seed, stop and budget are set here).
  RefineOptions refine_options{96, 30};
};

/// One stage's outcome: the flown cost after it, and the seconds since the start at its end.
struct FlownStage {
  std::string name;  ///< "walk" (the roadmap walk), "shortcut", then "corridor" and "refine" per round.
  double cost = 0.0;
  double seconds = 0.0;
};

/// The flown tour and how each stage got it there.
struct FlownTour {
  std::vector<Vec3> stops;  ///< Closed: front() == back() == the root. Straight segments between.
  double cost = 0.0;        ///< Its length.
  double walk_cost = 0.0;   ///< The roadmap walk's (stage 1's search).
  std::vector<FlownStage> stages;
  GipResult search;                ///< Stage 1: the walk, its targets, trace and proven bound (on roadmap walks).
  ShortcutTour roadmap_shortcut;   ///< Stage 1's shortcut of the walk (its stops are roadmap vertices).
  std::size_t graph_vertices = 0;  ///< Of the graph the flown tour was last searched on.
  std::size_t graph_edges = 0;
  std::size_t corridor_samples = 0;  ///< Tube samples of the corridor rounds that shortened the tour.
  std::size_t segments_checked = 0;  ///< By shortcuts, corridors and refinement.
  RefineResult refined;              ///< The last refinement's.
  FlownTourCheck check;              ///< The independent check; its `sees` says what each stop sees.
  bool stopped = false;              ///< The stop or the budget cut a stage short (the tour is still sound).
};

/// Runs the pipeline on `graph` (the roadmap's, root 0; positions[v] places vertex v) in `scene`
/// (the roadmap's scene: its POI ids are the graph's). Throws as solve_gip does on bad options,
/// and std::invalid_argument when positions do not cover the graph or root 0 is not the scene's
/// root.
[[nodiscard]] FlownTour fly_tour(const Scene& scene, const InspectionGraph& graph, std::span<const Vec3> positions,
                                 const FlownTourOptions& options);

}  // namespace ispars::planning
