#include "ispars/planning/tour/quick_tour.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>

namespace ispars::planning {
namespace {

constexpr double kUnreached = std::numeric_limits<double>::infinity();

// Dijkstra from `source` until `done(v)` holds for a settled v; appends the path to `walk`
// (without `source`) and returns v, or kNoVertex when stopped or nothing qualifies.
class LocalSearch {
 public:
  explicit LocalSearch(const InspectionGraph& g)
      : g_(g), dist_(g.vertex_count(), kUnreached), parent_(g.vertex_count()) {}

  template <class Done>
  VertexId walk_to(VertexId source, Done&& done, std::vector<VertexId>& walk, const std::atomic<bool>* stop) {
    for (const VertexId v : touched_) dist_[v] = kUnreached;
    touched_.clear();
    using Item = std::pair<double, VertexId>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    dist_[source] = 0.0;
    touched_.push_back(source);
    open.push({0.0, source});
    std::size_t pops = 0;
    while (!open.empty()) {
      if ((++pops & 4095u) == 0 && stop != nullptr && stop->load()) return kNoVertex;
      const auto [d, v] = open.top();
      open.pop();
      if (d > dist_[v]) continue;
      if (v != source && done(v)) {
        std::vector<VertexId> leg;
        for (VertexId x = v; x != source; x = parent_[x]) leg.push_back(x);
        walk.insert(walk.end(), leg.rbegin(), leg.rend());
        return v;
      }
      for (const Neighbor& n : g_.neighbors(v)) {
        const double nd = d + n.cost;
        if (nd < dist_[n.vertex]) {
          if (dist_[n.vertex] == kUnreached) touched_.push_back(n.vertex);
          dist_[n.vertex] = nd;
          parent_[n.vertex] = v;
          open.push({nd, n.vertex});
        }
      }
    }
    return kNoVertex;
  }

 private:
  const InspectionGraph& g_;
  std::vector<double> dist_;
  std::vector<VertexId> parent_;
  std::vector<VertexId> touched_;
};

}  // namespace

std::optional<InspectionTour> nearest_viewpoint_tour(const InspectionGraph& g, VertexId root,
                                                     const std::vector<PoiId>& targets, const std::atomic<bool>* stop) {
  std::vector<char> wanted(g.poi_count(), 0);
  std::size_t unseen = 0;
  for (const PoiId p : targets) unseen += !wanted[p] && (wanted[p] = 1);
  InspectionTour tour;
  tour.walk = {root};
  const auto see = [&](VertexId v) {
    for (const PoiId p : g.visible(v)) {
      if (wanted[p]) {
        wanted[p] = 0;
        --unseen;
      }
    }
  };
  see(root);
  LocalSearch search(g);
  VertexId at = root;
  while (unseen > 0) {
    const std::size_t from = tour.walk.size();
    const VertexId next = search.walk_to(
        at,
        [&](VertexId v) {
          const auto seen = g.visible(v);
          return std::any_of(seen.begin(), seen.end(), [&](PoiId p) { return wanted[p] != 0; });
        },
        tour.walk, stop);
    if (next == kNoVertex) return std::nullopt;  // stopped (targets are all reachable)
    for (std::size_t i = from; i < tour.walk.size(); ++i) see(tour.walk[i]);
    at = next;
  }
  if (at != root && search.walk_to(
                        at, [&](VertexId v) { return v == root; }, tour.walk, stop) == kNoVertex) {
    return std::nullopt;
  }
  for (std::size_t i = 1; i < tour.walk.size(); ++i) tour.cost += g.edge_cost(tour.walk[i - 1], tour.walk[i]);
  tour.covered = targets;
  std::sort(tour.covered.begin(), tour.covered.end());
  tour.covered.erase(std::unique(tour.covered.begin(), tour.covered.end()), tour.covered.end());
  return tour;
}

}  // namespace ispars::planning
