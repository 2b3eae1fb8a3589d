#include "ispars/planning/tour/cut_separation.hpp"

#include <algorithm>
#include <limits>

namespace ispars::planning {
namespace {

constexpr double kResidual = 1e-9;

}  // namespace

CutGraph CutGraph::of_component(const InspectionGraph& graph, VertexId root, std::span<const PoiId> targets) {
  CutGraph g;
  const std::vector<VertexId> component = graph.component_of(root);
  std::vector<std::uint32_t> local(graph.vertex_count(), std::numeric_limits<std::uint32_t>::max());
  for (std::size_t i = 0; i < component.size(); ++i) local[component[i]] = static_cast<std::uint32_t>(i);
  g.vertex_count = component.size();
  g.root = local[root];
  for (const RoadmapEdge& e : graph.edges()) {
    if (e.u == e.v || local[e.u] == std::numeric_limits<std::uint32_t>::max()) continue;
    g.edges.emplace_back(local[e.u], local[e.v]);
    g.costs.push_back(e.cost);
  }
  std::vector<char> wanted(graph.poi_count(), 0);
  for (const PoiId p : targets) wanted[p] = 1;
  for (const PoiId p : graph.visible(root)) wanted[p] = 0;  // seen at the start of every tour
  std::vector<std::vector<std::uint32_t>> by_poi(graph.poi_count());
  for (const VertexId v : component) {
    for (const PoiId p : graph.visible(v)) {
      if (wanted[p]) by_poi[p].push_back(local[v]);
    }
  }
  for (auto& group : by_poi) {
    if (!group.empty()) g.groups.push_back(std::move(group));
  }
  std::sort(g.groups.begin(), g.groups.end());
  g.groups.erase(std::unique(g.groups.begin(), g.groups.end()), g.groups.end());
  return g;
}

void MaxFlow::set_capacities(const double* x) {
  const CutGraph& g = *graph_;
  to_.clear();
  capacity_.clear();
  std::vector<std::uint32_t> degree(g.vertex_count + 1, 0);
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    if (!(x[e] > kResidual)) continue;
    const auto [u, v] = g.edges[e];
    to_.push_back(v);
    to_.push_back(u);
    capacity_.push_back(x[e]);
    capacity_.push_back(x[e]);
    ++degree[u];
    ++degree[v];
  }
  offsets_.assign(g.vertex_count + 1, 0);
  for (std::size_t v = 0; v < g.vertex_count; ++v) offsets_[v + 1] = offsets_[v] + degree[v];
  arcs_.assign(to_.size(), 0);
  std::vector<std::uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::uint32_t a = 0; a < to_.size(); ++a) {
    const std::uint32_t from = to_[a ^ 1u];  // an arc leaves where its partner arrives
    arcs_[fill[from]++] = a;
  }
  residual_ = capacity_;
  member_.assign(g.vertex_count, 0);
  level_.assign(g.vertex_count, -1);
  next_arc_.assign(g.vertex_count, 0);
}

bool MaxFlow::levels() {
  std::fill(level_.begin(), level_.end(), -1);
  std::vector<std::uint32_t> queue{graph_->root};
  level_[graph_->root] = 0;
  bool reached = false;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const std::uint32_t v = queue[head];
    if (member_[v]) {  // joined to the sink: a path ends here
      reached = true;
      continue;
    }
    for (std::uint32_t k = offsets_[v]; k < offsets_[v + 1]; ++k) {
      const std::uint32_t a = arcs_[k];
      if (residual_[a] > kResidual && level_[to_[a]] < 0) {
        level_[to_[a]] = level_[v] + 1;
        queue.push_back(to_[a]);
      }
    }
  }
  return reached;
}

double MaxFlow::push(std::uint32_t v, double amount) {
  if (member_[v]) return amount;  // the implicit arc to the sink has no capacity limit
  for (std::uint32_t& k = next_arc_[v]; k < offsets_[v + 1]; ++k) {
    const std::uint32_t a = arcs_[k];
    const std::uint32_t w = to_[a];
    if (residual_[a] <= kResidual || level_[w] != level_[v] + 1) continue;
    const double pushed = push(w, std::min(amount, residual_[a]));
    if (pushed > 0.0) {
      residual_[a] -= pushed;
      residual_[a ^ 1u] += pushed;
      return pushed;
    }
  }
  return 0.0;
}

double MaxFlow::max_flow_to(std::span<const std::uint32_t> group, double limit) {
  residual_ = capacity_;
  std::fill(member_.begin(), member_.end(), 0);
  for (const std::uint32_t v : group) member_[v] = 1;
  double flow = 0.0;
  while (flow < limit && levels()) {
    for (std::size_t v = 0; v < next_arc_.size(); ++v) next_arc_[v] = offsets_[v];
    for (double pushed; flow < limit && (pushed = push(graph_->root, limit - flow)) > 0.0;) flow += pushed;
  }
  return flow;
}

std::vector<char> MaxFlow::source_side() const {
  std::vector<char> in_s(graph_->vertex_count, 0);
  std::vector<std::uint32_t> stack{graph_->root};
  in_s[graph_->root] = 1;
  while (!stack.empty()) {
    const std::uint32_t v = stack.back();
    stack.pop_back();
    for (std::uint32_t k = offsets_[v]; k < offsets_[v + 1]; ++k) {
      const std::uint32_t a = arcs_[k];
      if (residual_[a] > kResidual && !in_s[to_[a]]) {
        in_s[to_[a]] = 1;
        stack.push_back(to_[a]);
      }
    }
  }
  return in_s;
}

std::vector<char> MaxFlow::sink_side_complement() const {
  // Vertices that reach a member: backwards from the members, along arcs with residual left.
  std::vector<char> reaches(graph_->vertex_count, 0);
  std::vector<std::uint32_t> stack;
  for (std::uint32_t v = 0; v < graph_->vertex_count; ++v) {
    if (member_[v]) {
      reaches[v] = 1;
      stack.push_back(v);
    }
  }
  while (!stack.empty()) {
    const std::uint32_t w = stack.back();
    stack.pop_back();
    for (std::uint32_t k = offsets_[w]; k < offsets_[w + 1]; ++k) {
      const std::uint32_t back = arcs_[k] ^ 1u;  // the arc from to_[arcs_[k]] into w
      const std::uint32_t u = to_[arcs_[k]];
      if (residual_[back] > kResidual && !reaches[u]) {
        reaches[u] = 1;
        stack.push_back(u);
      }
    }
  }
  std::vector<char> in_s(graph_->vertex_count, 0);
  for (std::size_t v = 0; v < in_s.size(); ++v) in_s[v] = reaches[v] ? 0 : 1;
  return in_s;
}

}  // namespace ispars::planning
