#pragma once
// A first tour in moments on a graph of any size, before the solver's distance rows exist: from
// the root, walk to the nearest vertex that sees a target not yet seen (one Dijkstra that stops
// there), repeat, then walk home. Every vertex passed on the way counts. Poor next to the
// solver's tours, but valid, and in hand long before a large instance's first closure tour.

#include <atomic>
#include <optional>
#include <vector>

#include "ispars/planning/tour/inspection_tour.hpp"
#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

/// The nearest-unseen-viewpoint walk for `targets` (all seen from the root's component), or
/// nothing when `stop` is set first. Its cost is the sum of its steps' cheapest edges.
[[nodiscard]] std::optional<InspectionTour> nearest_viewpoint_tour(const InspectionGraph& graph, VertexId root,
                                                                   const std::vector<PoiId>& targets,
                                                                   const std::atomic<bool>* stop);

}  // namespace ispars::planning
