#pragma once
// A proven lower bound on the graph inspection planning optimum, from linear programming.
//
// The group cut relaxation: one variable x_e >= 0 per edge of the root's component (how often a
// tour walks it), minimise sum c_e x_e subject to x(delta(S)) >= 2 for every target p and every
// vertex set S that holds the root and no vertex seeing p. A closed walk from the root that sees
// p leaves S and comes back, so it crosses delta(S) at least twice: every tour is feasible, and
// the LP optimum over any subset of these cuts is a lower bound. Violated cuts are found by
// max-flow from the root to the vertices seeing p, on the support of the current LP solution,
// and added round after round (COIN-OR Clp, dual simplex warm starts).
//
// The bound reported is never the solver's objective as printed: it is recomputed from the LP
// dual, scaled down until it is exactly dual feasible, less a relative 1e-9 for rounding.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

/// Bytes the LP holds per constraint nonzero at its cap, for memory leases. Measured, not proven:
/// bridge_n1000 (all edges, 60 s) peaked at 180 MB with 3,000,000 nonzeros beside a 25 MB search
/// (about 52 bytes each); rounded up.
inline constexpr double kLpBytesPerNonzero = 64.0;

struct TourBoundOptions {
  VertexId root = 0;
  /// Targets, each seen by some vertex of the root's component (solve_gip checks this).
  std::vector<PoiId> targets;
  double budget_seconds = 10.0;
  /// When set and returning true, the rounds stop (within one simplex iteration or one max-flow)
  /// and the best bound so far is returned.
  std::function<bool()> should_stop;
  /// Above this many edges in the graph the LP is not attempted (one column per edge).
  std::size_t max_edges = 500'000;
  /// The LP's size cap, in constraint nonzeros (kLpBytesPerNonzero each). Past half of
  /// it, every cut whose dual is 0 is dropped (the LP's optimum is unchanged: its dual stays
  /// feasible with the same objective) and may be found again later; a round adds cuts only while
  /// they fit, and when none fits the rounds stop (`capped`) with the bound proven so far.
  std::size_t max_cut_nonzeros = 3'000'000;
  /// Called (from the bounding thread) whenever the proven bound rises.
  std::function<void(double seconds, double bound)> on_improvement;
};

struct TourBoundResult {
  double bound = 0.0;             ///< Proven: no tour seeing every target is shorter.
  bool complete = false;          ///< No violated cut is left: the LP optimum over all cuts.
  std::size_t rounds = 0;         ///< LP solves.
  std::size_t cuts = 0;           ///< Rows added.
  std::size_t dropped = 0;        ///< Rows dropped at the size cap (their dual was 0).
  std::size_t peak_nonzeros = 0;  ///< The LP's constraint nonzeros at their most.
  bool capped = false;            ///< The cap stopped the rounds: the cuts that bind fill it.
  double seconds = 0.0;           ///< Wall time of the rounds (the bound depends on it: a budget stops them).
  std::vector<std::pair<double, double>> trace;  ///< (seconds, bound) at each rise.
  std::string skipped;                           ///< Non-empty when no LP was solved, and why.
};

/// Runs the cutting-plane loop until no cut is violated, the budget ends or should_stop() holds.
[[nodiscard]] TourBoundResult lp_tour_bound(const InspectionGraph& graph, const TourBoundOptions& options);

}  // namespace ispars::planning
