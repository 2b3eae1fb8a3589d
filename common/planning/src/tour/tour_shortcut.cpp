#include "ispars/planning/tour/tour_shortcut.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace ispars::planning {
namespace {

constexpr double kShorterBy = 1e-9;  // a straight step must be shorter than the walk by this

// The stops of one pass and what they see: local target ids per stop, and how many stops see
// each target.
struct Stops {
  std::vector<VertexId> vertex;
  std::vector<std::vector<std::uint32_t>> sees;
  std::vector<std::size_t> count;
};

Stops make_stops(const InspectionGraph& graph, std::span<const PoiId> targets, std::vector<VertexId> vertex) {
  Stops s;
  s.vertex = std::move(vertex);
  s.count.assign(targets.size(), 0);
  for (const VertexId v : s.vertex) {
    std::vector<std::uint32_t> local;
    for (const PoiId p : graph.visible(v)) {
      const auto it = std::lower_bound(targets.begin(), targets.end(), p);
      if (it != targets.end() && *it == p) local.push_back(static_cast<std::uint32_t>(it - targets.begin()));
    }
    for (const auto t : local) ++s.count[t];
    s.sees.push_back(std::move(local));
  }
  return s;
}

// The farthest j such that stops i+1 .. j-1 can all go with every target still seen.
// `count` is how many kept stops see each target now.
std::size_t farthest_by_coverage(const Stops& s, const std::vector<std::size_t>& count, std::size_t i, std::size_t last,
                                 std::vector<std::size_t>& removed) {
  std::size_t j = i + 1;
  std::vector<std::uint32_t> touched;
  for (; j < last; ++j) {  // may stop j go too?
    bool breaks = false;
    for (const auto t : s.sees[j]) breaks = breaks || removed[t] + 1 >= count[t];
    if (breaks) break;
    for (const auto t : s.sees[j]) {
      ++removed[t];
      touched.push_back(t);
    }
  }
  for (const auto t : touched) removed[t] = 0;
  return j;
}

// One pass: from each kept stop, the farthest stop within the window that the coverage, the
// length and the collision checker allow. Returns the kept stops.
std::vector<VertexId> one_pass(const Stops& s, std::span<const Vec3> positions, const SegmentValid& segment_valid,
                               const ShortcutOptions& o, std::chrono::steady_clock::time_point deadline,
                               ShortcutTour& out) {
  const std::size_t n = s.vertex.size();
  std::vector<double> along(n, 0.0);  // walk length from stop 0
  for (std::size_t k = 1; k < n; ++k) {
    along[k] = along[k - 1] + (positions[s.vertex[k]] - positions[s.vertex[k - 1]]).norm();
  }
  std::vector<std::size_t> removed(s.count.size(), 0);
  std::vector<std::size_t> count = s.count;
  std::vector<VertexId> kept{s.vertex[0]};
  for (std::size_t i = 0; i + 1 < n;) {
    std::size_t next = i + 1;
    const bool stopped = (o.stop != nullptr && o.stop->load()) ||
                         (o.budget_seconds > 0.0 && std::chrono::steady_clock::now() >= deadline);
    out.stopped = out.stopped || stopped;
    const std::size_t reach = stopped ? i + 1 : std::min(farthest_by_coverage(s, count, i, n, removed), i + o.window);
    for (std::size_t j = std::min(reach, n - 1); j >= i + 2; --j) {
      const Vec3& a = positions[s.vertex[i]];
      const Vec3& b = positions[s.vertex[j]];
      if ((b - a).norm() >= along[j] - along[i] - kShorterBy) continue;  // no shorter
      if (s.vertex[i] != s.vertex[j]) {
        ++out.segments_checked;
        if (!segment_valid(a, b)) continue;
      }
      for (std::size_t k = i + 1; k < j; ++k) {
        for (const auto t : s.sees[k]) --count[t];
      }
      next = j;
      ++out.shortcuts;
      break;
    }
    if (s.vertex[next] != kept.back()) kept.push_back(s.vertex[next]);
    i = next;
  }
  return kept;
}

}  // namespace

ShortcutTour shortcut_tour(const InspectionGraph& graph, std::span<const Vec3> positions,
                           std::span<const PoiId> targets, const InspectionTour& tour,
                           const SegmentValid& segment_valid, const ShortcutOptions& options) {
  if (tour.walk.empty()) throw std::invalid_argument("shortcut_tour: the walk is empty");
  if (positions.size() < graph.vertex_count()) {
    throw std::invalid_argument(
        fmt::format("shortcut_tour: {} positions for {} vertices", positions.size(), graph.vertex_count()));
  }
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(std::clamp(options.budget_seconds, 0.0, 1e6)));
  ShortcutTour out;
  std::vector<VertexId> stops;
  for (const VertexId v : tour.walk) {
    if (stops.empty() || stops.back() != v) stops.push_back(v);
  }
  for (std::size_t pass = 0; pass < options.max_passes && stops.size() > 2; ++pass) {
    const std::size_t before = out.shortcuts;
    stops = one_pass(make_stops(graph, targets, std::move(stops)), positions, segment_valid, options, deadline, out);
    if (out.shortcuts == before || out.stopped) break;
  }
  out.stops = std::move(stops);
  for (std::size_t k = 0; k < out.stops.size(); ++k) {
    out.path.push_back(positions[out.stops[k]]);
    if (k > 0) out.cost += (out.path[k] - out.path[k - 1]).norm();
  }
  return out;
}

ShortcutValidation check_shortcut_tour(const InspectionGraph& graph, std::span<const Vec3> positions, VertexId root,
                                       std::span<const PoiId> targets, const ShortcutTour& tour,
                                       const SegmentValid& segment_valid) {
  ShortcutValidation v;
  const auto fail = [&](std::string problem) {
    if (v.problem.empty()) v.problem = std::move(problem);
  };
  v.closed = !tour.stops.empty() && tour.stops.front() == root && tour.stops.back() == root;
  if (!v.closed) fail("the tour does not start and end at the root");
  v.steps_valid = true;
  for (std::size_t k = 1; k < tour.stops.size(); ++k) {
    const VertexId a = tour.stops[k - 1], b = tour.stops[k];
    if (a >= graph.vertex_count() || b >= graph.vertex_count()) {
      v.steps_valid = false;
      fail(fmt::format("step {} names a vertex outside the graph", k));
      break;
    }
    v.recomputed_cost += (positions[b] - positions[a]).norm();
    if (a == b || graph.edge_cost(a, b) >= 0 || segment_valid(positions[a], positions[b])) continue;
    v.steps_valid = false;
    fail(fmt::format("step {} ({} -> {}) is neither an edge nor a valid segment", k, a, b));
  }
  std::vector<char> seen(targets.size(), 0);
  for (const VertexId s : tour.stops) {
    if (s >= graph.vertex_count()) continue;
    for (const PoiId p : graph.visible(s)) {
      const auto it = std::lower_bound(targets.begin(), targets.end(), p);
      if (it != targets.end() && *it == p) seen[static_cast<std::size_t>(it - targets.begin())] = 1;
    }
  }
  const auto missing = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 0));
  v.covers_targets = missing == 0;
  if (!v.covers_targets) fail(fmt::format("{} targets are seen from no stop", missing));
  if (std::abs(v.recomputed_cost - tour.cost) > 1e-9 * std::max(1.0, v.recomputed_cost)) {
    fail(fmt::format("the stated cost {} is not the steps' length {}", tour.cost, v.recomputed_cost));
  }
  return v;
}

}  // namespace ispars::planning
