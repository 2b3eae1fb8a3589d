#pragma once
// An anytime solver for graph inspection planning (GIP): the shortest closed walk from the root
// whose vertices see every target POI.
//
// On the metric closure of the vertices that see targets: a randomized greedy covering tour
// (cost per newly seen target, cheapest insertion), then local search (drop a vertex whose POIs
// stay seen, 2-opt, Or-opt, replace a vertex by a cheaper one that sees what only it saw) and
// large-neighbourhood search (remove random, segment or related vertices; repair greedily; accept
// by simulated annealing) until the budget ends. Each thread runs its own chain from its own
// seed; the trajectory of every chain is fixed by (seed, thread index), so a run capped by
// iterations is deterministic, and a run capped by time differs only in where it stops.

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ispars/planning/tour/inspection_tour.hpp"
#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

struct GipOptions {
  VertexId root = 0;
  /// Targets; default (nullopt): every POI seen by a vertex of the root's component.
  std::optional<std::vector<PoiId>> targets;
  double budget_seconds = 10.0;
  /// Stop after this many large-neighbourhood iterations per thread (0: only the budget).
  std::uint64_t max_iterations = 0;
  std::uint64_t seed = 1;
  unsigned threads = 1;
  /// A closed walk from the root to start from (a warm start): the first chain begins with the
  /// tour through its vertices that see targets, in walk order, so the result is never costlier
  /// than the walk (when the walk sees every target). Empty: every chain builds its own.
  std::vector<VertexId> initial_walk;
  /// Called (under a lock, from any solver thread) when the best tour improves.
  std::function<void(double seconds, double cost)> on_improvement;
  /// When set and true, the search stops early and returns the best tour so far.
  const std::atomic<bool>* stop = nullptr;
  /// Prove a lower bound by linear programming (tour_bound.hpp) beside the search, on one more
  /// thread, until the LP is solved over all its cuts, `stop` is set or its own budget ends;
  /// solve_gip returns when both are done.
  bool lp_bound = true;
  /// The LP's wall-clock budget in seconds (0: budget_seconds; when that is 0 too, the bound
  /// stops when the search ends).
  double bound_seconds = 0.0;
  /// Called (under a lock, from the bounding thread) when the proven bound rises.
  std::function<void(double seconds, double bound)> on_bound;
};

struct GipResult {
  InspectionTour tour;
  std::vector<PoiId> targets;
  std::vector<std::pair<double, double>> trace;  ///< (seconds, best cost) at each improvement.
  std::optional<double> lower_bound;  ///< Proven: no tour in the graph is shorter (never over a thinned set).
  std::vector<std::pair<double, double>> bound_trace;  ///< (seconds, proven bound) at each rise.
  bool bound_complete = false;                         ///< The LP was solved over all its cuts.
  std::size_t bound_rounds = 0;                        ///< LP solves.
  std::size_t bound_cuts = 0;                          ///< LP rows added.
  std::size_t bound_dropped = 0;                       ///< LP rows dropped at its size cap (tour_bound.hpp).
  std::size_t bound_peak_nonzeros = 0;                 ///< The LP's constraint nonzeros at their most.
  std::string bound_note;                              ///< Why no LP bound was computed, when none was.
  double seconds = 0.0;
  std::uint64_t iterations = 0;   ///< Large-neighbourhood iterations, all threads.
  std::size_t candidates = 0;     ///< Vertices of the metric closure.
  std::size_t distance_rows = 0;  ///< Dijkstra rows computed (tour_closure.hpp).
  std::size_t thinned = 0;        ///< Target-seeing vertices left out (tour_closure.hpp).
  TourValidation validation;
};

/// Solves; throws InputError (file "tour", field "root" or "targets") when the root has no edges,
/// the target set is empty, a target id is unknown, or targets are not seen from the root's
/// component.
[[nodiscard]] GipResult solve_gip(const InspectionGraph& graph, const GipOptions& options);

}  // namespace ispars::planning
