#pragma once
// A tour for graph inspection planning, and its independent validation.

#include <string>
#include <vector>

#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

/// A closed walk from the root: walk.front() == walk.back() == root; each step is an edge.
struct InspectionTour {
  std::vector<VertexId> walk;
  double cost = 0.0;
  std::vector<PoiId> covered;  ///< Targets seen along the walk, ascending.
};

/// What validate_tour found; valid() when every check holds.
struct TourValidation {
  bool closed = false;  ///< Starts and ends at the root.
  bool steps_are_edges = false;
  bool covers_targets = false;
  bool cost_matches = false;  ///< The stated cost equals the sum of the steps' edge costs.
  double recomputed_cost = 0.0;
  std::size_t missing_targets = 0;
  std::string problem;  ///< The first failure, in words.
  [[nodiscard]] bool valid() const { return closed && steps_are_edges && covers_targets && cost_matches; }
};

/// Checks a tour from scratch against the graph, independent of the solver: closed at `root`,
/// every step an edge (its cheapest cost counted), every target seen, cost = sum of edge costs
/// (to 1e-9 relative).
[[nodiscard]] TourValidation validate_tour(const InspectionGraph& graph, VertexId root,
                                           const std::vector<PoiId>& targets, const InspectionTour& tour);

}  // namespace ispars::planning
