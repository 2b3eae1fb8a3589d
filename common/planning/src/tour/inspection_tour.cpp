#include "ispars/planning/tour/inspection_tour.hpp"

#include <fmt/format.h>

#include <cmath>

namespace ispars::planning {

TourValidation validate_tour(const InspectionGraph& graph, VertexId root, const std::vector<PoiId>& targets,
                             const InspectionTour& tour) {
  TourValidation v;
  const auto fail = [&](std::string problem) {
    if (v.problem.empty()) v.problem = std::move(problem);
  };
  v.closed = !tour.walk.empty() && tour.walk.front() == root && tour.walk.back() == root;
  if (!v.closed) fail(fmt::format("the walk does not start and end at the root {}", root));
  v.steps_are_edges = true;
  double cost = 0.0;
  for (std::size_t i = 0; i < tour.walk.size(); ++i) {
    if (tour.walk[i] >= graph.vertex_count()) {
      v.steps_are_edges = false;
      fail(fmt::format("step {} names vertex {} outside the graph", i, tour.walk[i]));
      break;
    }
    if (i == 0 || tour.walk[i] == tour.walk[i - 1]) continue;  // staying put costs nothing
    const double c = graph.edge_cost(tour.walk[i - 1], tour.walk[i]);
    if (c < 0) {
      v.steps_are_edges = false;
      fail(fmt::format("step {}: {}-{} is not an edge", i, tour.walk[i - 1], tour.walk[i]));
      break;
    }
    cost += c;
  }
  v.recomputed_cost = cost;
  v.cost_matches = v.steps_are_edges && std::abs(cost - tour.cost) <= 1e-9 * std::max(1.0, std::abs(cost));
  if (v.steps_are_edges && !v.cost_matches)
    fail(fmt::format("stated cost {} but the edges sum to {}", tour.cost, cost));
  std::vector<char> seen(graph.poi_count(), 0);
  if (v.steps_are_edges) {
    for (const VertexId x : tour.walk) {
      for (const PoiId p : graph.visible(x)) seen[p] = 1;
    }
  }
  for (const PoiId p : targets) {
    if (p >= seen.size() || !seen[p]) ++v.missing_targets;
  }
  v.covers_targets = v.steps_are_edges && v.missing_targets == 0;
  if (v.steps_are_edges && !v.covers_targets) fail(fmt::format("{} targets are not seen", v.missing_targets));
  return v;
}

}  // namespace ispars::planning
