#pragma once
// Shortcut tours: the roadmap tour as a robot would fly it. After the search, stretches of the
// closed walk are replaced by straight segments the collision checker accepts, as long as every
// target stays seen from a stop that is kept. In the spirit of OMPL's PathSimplifier, but
// inspection-aware: a viewpoint may be skipped only when another kept stop sees what it saw.
//
// Every stop of a shortcut tour is a vertex of the tour's walk (a valid configuration), and
// every step between two stops is either a roadmap edge of the walk or a segment that passed
// `segment_valid`; its cost is the sum of the steps' Euclidean lengths, never above the walk's.

#include <atomic>
#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "ispars/planning/tour/inspection_tour.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// A tour shortened by straight segments: closed (front == back == the root's stop).
struct ShortcutTour {
  std::vector<VertexId> stops;       ///< Walk vertices kept, in flying order.
  std::vector<Vec3> path;            ///< Their positions.
  double cost = 0.0;                 ///< Sum of the straight steps' lengths.
  std::size_t segments_checked = 0;  ///< Calls to segment_valid.
  std::size_t shortcuts = 0;         ///< Stretches replaced by one segment.
  bool stopped = false;              ///< `stop` or the budget ended it: the path is shortened only in part.
};

struct ShortcutOptions {
  /// From each stop, the farthest stop tried is this many stops ahead (bounds the checks to
  /// window x stops per pass).
  std::size_t window = 48;
  /// Passes over the tour, until one changes nothing.
  std::size_t max_passes = 4;
  /// When set and true, shortening stops and the path so far is returned (still valid).
  const std::atomic<bool>* stop = nullptr;
  /// When > 0, shortening stops as `stop` does once this many seconds have passed (checked before
  /// each stop's candidates: at most `window` segment checks later). 0: no limit (deterministic).
  double budget_seconds = 0.0;
};

/// True when the straight motion from a to b is collision-free (Scene::segment_valid).
using SegmentValid = std::function<bool(const Vec3& a, const Vec3& b)>;

/// Shortens `tour` (a closed walk of `graph`, whose vertex v sits at positions[v]) keeping a stop
/// that sees each of `targets` (ascending). Deterministic: the same input gives the same path.
/// Throws std::invalid_argument when positions do not cover the graph or the walk is empty.
[[nodiscard]] ShortcutTour shortcut_tour(const InspectionGraph& graph, std::span<const Vec3> positions,
                                         std::span<const PoiId> targets, const InspectionTour& tour,
                                         const SegmentValid& segment_valid, const ShortcutOptions& options = {});

/// What check_shortcut_tour found; empty `problem` when the tour is sound.
struct ShortcutValidation {
  bool closed = false;
  bool covers_targets = false;
  bool steps_valid = false;  ///< Every step is a graph edge or passes segment_valid.
  double recomputed_cost = 0.0;
  std::string problem;
  [[nodiscard]] bool valid() const { return problem.empty(); }
};

/// Checks a shortcut tour from scratch: closed at `root`, every target seen from a stop, every
/// step an edge of the graph or a valid segment, the cost the sum of the steps' lengths.
[[nodiscard]] ShortcutValidation check_shortcut_tour(const InspectionGraph& graph, std::span<const Vec3> positions,
                                                     VertexId root, std::span<const PoiId> targets,
                                                     const ShortcutTour& tour, const SegmentValid& segment_valid);

}  // namespace ispars::planning
