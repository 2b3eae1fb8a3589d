#pragma once
// The graph of the LP tour bound (tour_bound.hpp), and the max-flow that separates its cuts.

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

/// The root's component with local vertex ids: its edges (one LP column each) and, per target,
/// the group of vertices seeing it. Targets the root sees are left out (every tour sees them);
/// identical groups appear once.
struct CutGraph {
  std::size_t vertex_count = 0;
  std::uint32_t root = 0;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::vector<double> costs;
  std::vector<std::vector<std::uint32_t>> groups;

  [[nodiscard]] static CutGraph of_component(const InspectionGraph& graph, VertexId root,
                                             std::span<const PoiId> targets);
};

/// Dinic's max-flow from the root to a group (every member joined to an implicit sink), on
/// edge capacities x (undirected: x_e each way). Edges with x_e ~ 0 are left out, so a flow
/// runs over the LP solution's support only.
class MaxFlow {
 public:
  explicit MaxFlow(const CutGraph& graph) : graph_(&graph) {}

  /// Capacities, one per graph edge.
  void set_capacities(const double* x);
  /// The flow from the root to `group`, stopping once it reaches `limit`.
  double max_flow_to(std::span<const std::uint32_t> group, double limit);
  /// After a flow below its limit: the vertices the root still reaches in the residual graph.
  [[nodiscard]] std::vector<char> source_side() const;
  /// After a flow below its limit: the vertices that cannot reach the group in the residual
  /// graph (a cut as close to the group as the flow allows).
  [[nodiscard]] std::vector<char> sink_side_complement() const;

 private:
  bool levels();
  double push(std::uint32_t v, double amount);

  const CutGraph* graph_;
  // Arcs in pairs (2k, 2k + 1) of opposite direction; adjacency in CSR form.
  std::vector<std::uint32_t> to_;
  std::vector<double> capacity_, residual_;
  std::vector<std::uint32_t> offsets_, arcs_;
  std::vector<char> member_;
  std::vector<int> level_;
  std::vector<std::uint32_t> next_arc_;
};

}  // namespace ispars::planning
