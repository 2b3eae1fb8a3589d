#include "ispars/gip_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <queue>
#include <thread>

#include "ispars/input_error.hpp"
#include "ispars/random.hpp"
#include "ispars/quick_tour.hpp"
#include "ispars/tour_bound.hpp"
#include "ispars/tour_closure.hpp"

namespace ispars {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kEps = 1e-9;
// Above this many vertices in the root's component, a quick first tour comes before the search.
constexpr std::size_t kQuickTourAbove = 20'000;

// Dijkstra from `source` over the whole graph: distances and predecessors.
void dijkstra(const InspectionGraph& g, VertexId source, std::vector<double>& dist, std::vector<VertexId>* parent,
              VertexId stop_at = kNoVertex) {
  dist.assign(g.vertex_count(), kInf);
  if (parent) parent->assign(g.vertex_count(), kNoVertex);
  using Item = std::pair<double, VertexId>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  dist[source] = 0.0;
  open.push({0.0, source});
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > dist[v]) continue;
    if (v == stop_at) return;
    for (const Neighbor& n : g.neighbors(v)) {
      const double nd = d + n.cost;
      if (nd < dist[n.vertex]) {
        dist[n.vertex] = nd;
        if (parent) (*parent)[n.vertex] = v;
        open.push({nd, n.vertex});
      }
    }
  }
}

using Closure = TourClosure;

// A tour on the closure: seq[0] is the root; the tour closes back to it.
struct Solution {
  std::vector<std::uint32_t> seq;
  std::vector<std::uint32_t> count;  // per target: tour vertices seeing it
  std::vector<char> in_tour;         // per candidate
  double cost = 0.0;
  std::size_t uncovered = 0;
};

class Chain {
 public:
  Chain(const Closure& c, std::uint64_t seed) : c_(c), rng_(seed) {}

  double tour_cost(const std::vector<std::uint32_t>& seq) const {
    double cost = 0.0;
    for (std::size_t i = 0; i < seq.size(); ++i) cost += c_.d(seq[i], seq[(i + 1) % seq.size()]);
    return cost;
  }

  Solution empty() const {
    Solution s;
    s.seq = {0};
    s.count.assign(c_.seen_by.size(), 0);
    s.in_tour.assign(c_.n, 0);
    s.in_tour[0] = 1;
    c_.ensure_row(0);
    s.uncovered = c_.seen_by.size();
    add_coverage(s, 0);
    return s;
  }

  void add_coverage(Solution& s, std::uint32_t v) const {
    for (const auto t : c_.sees[v]) {
      if (s.count[t]++ == 0) --s.uncovered;
    }
  }
  void remove_coverage(Solution& s, std::uint32_t v) const {
    for (const auto t : c_.sees[v]) {
      if (--s.count[t] == 0) ++s.uncovered;
    }
  }

  // Cheapest insertion of v: (position after which to insert, added cost).
  std::pair<std::size_t, double> best_insertion(const Solution& s, std::uint32_t v) const {
    std::size_t best_i = 0;
    double best = kInf;
    const std::size_t m = s.seq.size();
    for (std::size_t i = 0; i < m; ++i) {
      const auto a = s.seq[i], b = s.seq[(i + 1) % m];
      const double delta = c_.d(a, v) + c_.d(v, b) - c_.d(a, b);
      if (delta < best) {
        best = delta;
        best_i = i;
      }
    }
    return {best_i, best};
  }

  void insert(Solution& s, std::uint32_t v, std::size_t after, double delta) const {
    c_.ensure_row(v);  // every tour vertex has its row: distances from the tour cost nothing more
    s.seq.insert(s.seq.begin() + static_cast<std::ptrdiff_t>(after + 1), v);
    s.in_tour[v] = 1;
    s.cost += delta;
    add_coverage(s, v);
  }

  void erase_at(Solution& s, std::size_t i) const {
    const std::size_t m = s.seq.size();
    const auto a = s.seq[i - 1], v = s.seq[i], b = s.seq[(i + 1) % m];
    s.cost -= c_.d(a, v) + c_.d(v, b) - c_.d(a, b);
    remove_coverage(s, v);
    s.in_tour[v] = 0;
    s.seq.erase(s.seq.begin() + static_cast<std::ptrdiff_t>(i));
  }

  // Target-driven repair: take the unseen targets in random order; for each still unseen, insert
  // the candidate seeing it with the cheapest (noisy) insertion.
  void repair_by_target(Solution& s, double noise) {
    std::vector<std::uint32_t> unseen;
    for (std::size_t t = 0; t < s.count.size(); ++t) {
      if (s.count[t] == 0) unseen.push_back(static_cast<std::uint32_t>(t));
    }
    for (std::size_t i = unseen.size(); i > 1; --i) {
      std::swap(unseen[i - 1], unseen[static_cast<std::size_t>(rng_.uniform01() * static_cast<double>(i)) % i]);
    }
    for (const auto t : unseen) {
      if (s.count[t] != 0) continue;
      std::uint32_t best_v = 0;
      std::size_t best_i = 0;
      double best_delta = 0.0, best_score = kInf;
      for (const auto v : c_.seen_by[t]) {
        const auto [i, delta] = best_insertion(s, v);
        const double score = delta * (1.0 + noise * rng_.uniform01());
        if (score < best_score) {
          best_score = score;
          best_v = v;
          best_i = i;
          best_delta = delta;
        }
      }
      insert(s, best_v, best_i, best_delta);
    }
  }

  // Greedy repair: insert the candidate with the least added cost per newly seen target until
  // every target is seen; `noise` randomises the choice.
  void repair(Solution& s, double noise) {
    std::vector<std::uint32_t> gain(c_.n, 0);
    std::vector<std::uint32_t> touched;
    while (s.uncovered > 0) {
      touched.clear();
      for (std::size_t t = 0; t < s.count.size(); ++t) {
        if (s.count[t] != 0) continue;
        for (const auto v : c_.seen_by[t]) {
          if (s.in_tour[v]) continue;
          if (gain[v]++ == 0) touched.push_back(v);
        }
      }
      std::uint32_t best_v = 0;
      std::size_t best_i = 0;
      double best_delta = 0.0, best_score = kInf;
      for (const auto v : touched) {
        const auto [i, delta] = best_insertion(s, v);
        double score = (delta + kEps) / gain[v];
        if (noise > 0) score *= 1.0 + noise * rng_.uniform01();
        if (score < best_score) {
          best_score = score;
          best_v = v;
          best_i = i;
          best_delta = delta;
        }
        gain[v] = 0;
      }
      insert(s, best_v, best_i, best_delta);
    }
  }

  // Removes vertices whose targets all stay seen, best saving first.
  bool drop_redundant(Solution& s) const {
    bool any = false;
    for (;;) {
      std::size_t best_i = 0;
      double best_saving = kEps;
      const std::size_t m = s.seq.size();
      for (std::size_t i = 1; i < m; ++i) {
        const auto v = s.seq[i];
        bool needed = false;
        for (const auto t : c_.sees[v]) {
          if (s.count[t] == 1) {
            needed = true;
            break;
          }
        }
        if (needed) continue;
        const double saving = c_.d(s.seq[i - 1], v) + c_.d(v, s.seq[(i + 1) % m]) - c_.d(s.seq[i - 1], s.seq[(i + 1) % m]);
        if (saving > best_saving) {
          best_saving = saving;
          best_i = i;
        }
      }
      if (best_i == 0) return any;
      erase_at(s, best_i);
      any = true;
    }
  }

  bool two_opt(Solution& s) const {
    bool any = false;
    const std::size_t m = s.seq.size();
    if (m < 4) return false;
    for (bool improved = true; improved;) {
      improved = false;
      for (std::size_t i = 0; i + 2 < m; ++i) {
        const auto a = s.seq[i], b = s.seq[i + 1];
        for (std::size_t j = i + 2; j < m; ++j) {
          const auto cc = s.seq[j], dd = s.seq[(j + 1) % m];
          if (dd == a) continue;
          const double delta = c_.d(a, cc) + c_.d(b, dd) - c_.d(a, b) - c_.d(cc, dd);
          if (delta < -kEps) {
            std::reverse(s.seq.begin() + static_cast<std::ptrdiff_t>(i + 1), s.seq.begin() + static_cast<std::ptrdiff_t>(j + 1));
            s.cost += delta;
            improved = any = true;
            break;
          }
        }
        if (improved) break;
      }
    }
    return any;
  }

  // Moves a segment of 1-3 vertices (not the root) to its best place, possibly reversed.
  bool or_opt(Solution& s) const {
    bool any = false;
    for (bool improved = true; improved;) {
      improved = false;
      const std::size_t m = s.seq.size();
      for (std::size_t len = 1; len <= 3 && !improved; ++len) {
        for (std::size_t i = 1; i + len <= m && !improved; ++i) {
          const auto prev = s.seq[i - 1], first = s.seq[i], last = s.seq[i + len - 1], next = s.seq[(i + len) % m];
          const double removed = c_.d(prev, first) + c_.d(last, next) - c_.d(prev, next);
          for (std::size_t j = 0; j < m && !improved; ++j) {
            if (j + 1 >= i && j < i + len) continue;  // inside or adjacent-before the segment
            const auto a = s.seq[j], b = s.seq[(j + 1) % m];
            const double fwd = c_.d(a, first) + c_.d(last, b) - c_.d(a, b);
            const double rev = c_.d(a, last) + c_.d(first, b) - c_.d(a, b);
            const double add = std::min(fwd, rev);
            if (add - removed < -kEps) {
              std::vector<std::uint32_t> seg(s.seq.begin() + static_cast<std::ptrdiff_t>(i),
                                             s.seq.begin() + static_cast<std::ptrdiff_t>(i + len));
              if (rev < fwd) std::reverse(seg.begin(), seg.end());
              std::vector<std::uint32_t> rest;
              rest.reserve(m);
              std::size_t insert_after = 0;
              for (std::size_t k = 0; k < m; ++k) {
                if (k >= i && k < i + len) continue;
                rest.push_back(s.seq[k]);
                if (k == j) insert_after = rest.size();
              }
              rest.insert(rest.begin() + static_cast<std::ptrdiff_t>(insert_after), seg.begin(), seg.end());
              s.seq = std::move(rest);
              s.cost += add - removed;
              improved = any = true;
            }
          }
        }
      }
    }
    return any;
  }

  // Replaces a tour vertex by a non-tour candidate that sees every target only it sees, when
  // that is cheaper.
  bool replace(Solution& s) const {
    bool any = false;
    for (std::size_t i = 1; i < s.seq.size(); ++i) {
      const auto v = s.seq[i];
      std::vector<std::uint32_t> critical;
      for (const auto t : c_.sees[v]) {
        if (s.count[t] == 1) critical.push_back(t);
      }
      if (critical.empty()) continue;
      std::uint32_t rarest = critical.front();
      for (const auto t : critical) {
        if (c_.seen_by[t].size() < c_.seen_by[rarest].size()) rarest = t;
      }
      const std::size_t m = s.seq.size();
      const auto prev = s.seq[i - 1], next = s.seq[(i + 1) % m];
      const double removal = c_.d(prev, v) + c_.d(v, next) - c_.d(prev, next);
      std::vector<std::uint32_t> without(s.seq);
      without.erase(without.begin() + static_cast<std::ptrdiff_t>(i));
      std::uint32_t best_u = 0;
      std::size_t best_pos = 0;
      double best_add = removal - kEps;
      for (const auto u : c_.seen_by[rarest]) {
        if (s.in_tour[u]) continue;
        bool covers = true;
        for (const auto t : critical) {
          if (!std::binary_search(c_.sees[u].begin(), c_.sees[u].end(), t)) {
            covers = false;
            break;
          }
        }
        if (!covers) continue;
        for (std::size_t j = 0; j < without.size(); ++j) {
          const auto a = without[j], b = without[(j + 1) % without.size()];
          const double add = c_.d(a, u) + c_.d(u, b) - c_.d(a, b);
          if (add < best_add) {
            best_add = add;
            best_u = u;
            best_pos = j;
          }
        }
      }
      if (best_u != 0) {
        erase_at(s, i);  // s.seq is now `without`
        insert(s, best_u, best_pos, best_add);
        any = true;
      }
    }
    return any;
  }

  void local_search(Solution& s) const {
    for (int round = 0; round < 50; ++round) {
      bool changed = drop_redundant(s);
      changed |= two_opt(s);
      changed |= or_opt(s);
      changed |= replace(s);
      if (!changed) break;
    }
    s.cost = tour_cost(s.seq);  // no drift from incremental updates
  }

  // Removes some tour vertices (never the root): random, a segment, or related to a seed vertex.
  void destroy(Solution& s) {
    const std::size_t m = s.seq.size();
    if (m <= 1) return;
    const std::size_t most = std::max<std::size_t>(2, (m - 1) * (rng_.uniform01() < 0.2 ? 6 : 3) / 10);
    const std::size_t k = 1 + static_cast<std::size_t>(rng_.uniform01() * static_cast<double>(most));
    const double kind = rng_.uniform01();
    std::vector<std::size_t> positions;
    if (kind < 0.35) {  // a contiguous segment
      const std::size_t start = 1 + static_cast<std::size_t>(rng_.uniform01() * static_cast<double>(m - 1));
      for (std::size_t p = start; p < m && positions.size() < k; ++p) positions.push_back(p);
    } else if (kind < 0.7) {  // related: a vertex and its nearest tour vertices
      const std::size_t centre = 1 + static_cast<std::size_t>(rng_.uniform01() * static_cast<double>(m - 1));
      std::vector<std::pair<double, std::size_t>> by_distance;
      for (std::size_t p = 1; p < m; ++p) by_distance.push_back({c_.d(s.seq[centre], s.seq[p]), p});
      std::sort(by_distance.begin(), by_distance.end());
      for (std::size_t q = 0; q < k && q < by_distance.size(); ++q) positions.push_back(by_distance[q].second);
    } else {  // random
      std::vector<std::size_t> all;
      for (std::size_t p = 1; p < m; ++p) all.push_back(p);
      for (std::size_t q = 0; q < k && !all.empty(); ++q) {
        const std::size_t pick = static_cast<std::size_t>(rng_.uniform01() * static_cast<double>(all.size()));
        positions.push_back(all[std::min(pick, all.size() - 1)]);
        all.erase(all.begin() + static_cast<std::ptrdiff_t>(std::min(pick, all.size() - 1)));
      }
    }
    std::sort(positions.begin(), positions.end(), std::greater<>());
    for (const std::size_t p : positions) erase_at(s, p);
  }

  Rng& rng() { return rng_; }

 private:
  const Closure& c_;
  Rng rng_;
};

std::vector<PoiId> choose_targets(const InspectionGraph& g, const GipOptions& o, const std::vector<VertexId>& component) {
  std::vector<char> seen(g.poi_count(), 0);
  for (const VertexId v : component) {
    for (const PoiId p : g.visible(v)) seen[p] = 1;
  }
  std::vector<PoiId> targets;
  if (!o.targets) {
    for (PoiId p = 0; p < g.poi_count(); ++p) {
      if (seen[p]) targets.push_back(p);
    }
    if (targets.empty()) throw InputError("tour", "targets", "no POI is seen from the root's component");
    return targets;
  }
  targets = *o.targets;
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  if (targets.empty()) throw InputError("tour", "targets", "the target set is empty");
  std::size_t unknown = 0, unreachable = 0;
  PoiId first_unknown = 0, first_unreachable = 0;
  for (const PoiId p : targets) {
    if (p >= g.poi_count()) {
      if (unknown++ == 0) first_unknown = p;
    } else if (!seen[p]) {
      if (unreachable++ == 0) first_unreachable = p;
    }
  }
  if (unknown > 0) {
    throw InputError("tour", "targets",
                     fmt::format("{} unknown POI ids (the first: {}; the graph has POIs 0..{})", unknown, first_unknown,
                                 g.poi_count() == 0 ? 0 : g.poi_count() - 1));
  }
  if (unreachable > 0) {
    throw InputError("tour", "targets",
                     fmt::format("{} targets are seen by no vertex reachable from the root (the first: POI {})",
                                 unreachable, first_unreachable));
  }
  return targets;
}

// The closed walk in the graph through the candidates of `seq`, in order.
InspectionTour expand(const InspectionGraph& g, const Closure& c, const std::vector<std::uint32_t>& seq) {
  InspectionTour tour;
  tour.walk.push_back(c.vertex[seq[0]]);
  std::vector<double> dist;
  std::vector<VertexId> parent;
  for (std::size_t i = 0; i < seq.size(); ++i) {
    const VertexId a = c.vertex[seq[i]], b = c.vertex[seq[(i + 1) % seq.size()]];
    if (a == b) continue;
    dijkstra(g, a, dist, &parent, b);
    std::vector<VertexId> leg;
    for (VertexId v = b; v != a; v = parent[v]) leg.push_back(v);
    tour.walk.insert(tour.walk.end(), leg.rbegin(), leg.rend());
  }
  for (std::size_t i = 1; i < tour.walk.size(); ++i) {
    if (tour.walk[i] == tour.walk[i - 1]) continue;
    tour.cost += g.edge_cost(tour.walk[i - 1], tour.walk[i]);
  }
  return tour;
}

}  // namespace

GipResult solve_gip(const InspectionGraph& g, const GipOptions& o) {
  const auto t0 = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  if (o.root >= g.vertex_count()) {
    throw InputError("tour", "root", fmt::format("vertex {} is not in the graph ({} vertices)", o.root, g.vertex_count()));
  }
  if (!(o.budget_seconds >= 0.0) || !std::isfinite(o.budget_seconds)) {
    throw InputError("tour", "budget", fmt::format("must be a finite number of seconds >= 0, got {}", o.budget_seconds));
  }
  if (g.neighbors(o.root).empty()) {
    // Only a root that sees every target by itself needs no edges.
    const auto sees = g.visible(o.root);
    const bool root_suffices =
        o.targets ? !o.targets->empty() && std::all_of(o.targets->begin(), o.targets->end(), [&](PoiId p) {
          return std::binary_search(sees.begin(), sees.end(), p);
        })
                  : !sees.empty();
    if (!root_suffices) {
      throw InputError("tour", "root", fmt::format("the root (vertex {}) has no edges: no tour can leave it", o.root));
    }
  }
  const std::vector<VertexId> component = g.component_of(o.root);
  GipResult result;
  result.targets = choose_targets(g, o, component);
  // The root alone sees every target: the tour is staying there.
  const auto root_sees = g.visible(o.root);
  if (std::all_of(result.targets.begin(), result.targets.end(), [&](PoiId p) {
        return std::binary_search(root_sees.begin(), root_sees.end(), p);
      })) {
    result.tour.walk = {o.root};
    result.tour.covered = result.targets;
    result.trace.push_back({elapsed(), 0.0});
    result.lower_bound = 0.0;
    result.candidates = 1;
    result.validation = validate_tour(g, o.root, result.targets, result.tour);
    result.seconds = elapsed();
    return result;
  }
  // The LP bound runs beside the search on its own thread, until the search ends.
  std::atomic<bool> abandon_bound{false};  // set when the search fails, or ends with no bound budget
  std::mutex bound_mutex;
  TourBoundResult bounded;
  std::thread bound_thread;
  if (o.lp_bound) {
    TourBoundOptions bo;
    bo.root = o.root;
    bo.targets = result.targets;
    bo.budget_seconds = o.bound_seconds > 0.0 ? o.bound_seconds : o.budget_seconds > 0.0 ? o.budget_seconds : 1e7;
    bo.should_stop = [&] { return abandon_bound.load() || (o.stop != nullptr && o.stop->load()); };
    const double offset = elapsed();
    bo.on_improvement = [&, offset](double seconds, double bound) {
      std::lock_guard lock(bound_mutex);
      result.bound_trace.emplace_back(offset + seconds, bound);
      if (o.on_bound) o.on_bound(offset + seconds, bound);
    };
    bound_thread = std::thread([&, bo] { bounded = lp_tour_bound(g, bo); });
  }
  struct JoinOnExit {  // if the search throws, the bounding thread is stopped and joined anyway
    std::atomic<bool>& done;
    std::thread& thread;
    ~JoinOnExit() {
      done = true;
      if (thread.joinable()) thread.join();
    }
  } join_on_exit{abandon_bound, bound_thread};
  const auto finish_bound = [&] {
    if (o.bound_seconds <= 0.0 && o.budget_seconds <= 0.0) abandon_bound = true;  // no budget of its own
    if (bound_thread.joinable()) bound_thread.join();
    result.lower_bound = std::max(result.lower_bound.value_or(0.0), bounded.bound);
    result.bound_complete = bounded.complete;
    result.bound_rounds = bounded.rounds;
    result.bound_cuts = bounded.cuts;
    result.bound_note = bounded.skipped;
  };
  // A large instance first gets a walk to the nearest unseen viewpoints (quick_tour.hpp), so a
  // tour is in hand within the budget even before the closure rows for a search tour exist.
  std::optional<InspectionTour> quick;
  if (component.size() > kQuickTourAbove) {
    quick = nearest_viewpoint_tour(g, o.root, result.targets, o.stop);
    if (quick) {
      result.trace.push_back({elapsed(), quick->cost});
      if (o.on_improvement) o.on_improvement(result.trace.back().first, quick->cost);
    }
  }
  const unsigned threads = std::max(1u, o.threads);
  TourClosureOptions closure_options;
  closure_options.threads = threads;
  // Rows ahead stop at the budget (the rest come on first use); a lazy row is refused after a stop.
  const bool timed = o.max_iterations == 0 || o.budget_seconds > 0;
  // With a quick tour in hand, lazy rows are refused past the budget too.
  closure_options.should_stop = [&, timed] {
    return (o.stop != nullptr && o.stop->load()) || (quick && timed && elapsed() >= o.budget_seconds);
  };
  closure_options.stop_rows_ahead = [&, timed] { return timed && elapsed() >= o.budget_seconds; };
  const Closure c(g, o.root, result.targets, component, closure_options);
  result.thinned = c.thinned;
  result.candidates = c.n;

  // A lower bound: every target needs a visit to some vertex seeing it, and a return.
  double bound = 0.0;
  try {
    for (const auto& covering : c.seen_by) {
      double best = kInf;
      for (const auto v : covering) best = std::min(best, c.d(0, v) + c.d(v, 0));
      bound = std::max(bound, best);
    }
  } catch (const ClosureStopped&) {
    bound = 0.0;  // stopped before the root's row: no simple bound
  }
  result.lower_bound = bound;

  std::mutex mutex;
  Solution best;
  best.cost = quick ? quick->cost : kInf;  // a search tour is offered only when it beats the quick one
  std::size_t best_chain = 0;
  std::atomic<std::uint64_t> iterations{0};
  const auto offer = [&](const Solution& s, std::size_t chain) {
    std::lock_guard lock(mutex);
    if (s.cost < best.cost - kEps || (std::abs(s.cost - best.cost) <= kEps && chain < best_chain)) {
      const bool improved = s.cost < best.cost - kEps;
      best = s;
      best_chain = chain;
      if (improved) {
        const double t = elapsed();
        result.trace.push_back({t, s.cost});
        if (o.on_improvement) o.on_improvement(t, s.cost);
      }
    }
  };
  const auto search_chain = [&](std::size_t index) {
    Chain chain(c, o.seed * 0x9E3779B97F4A7C15ull + index + 1);
    Solution current = chain.empty();
    chain.repair(current, index == 0 ? 0.0 : 0.3);
    chain.local_search(current);
    offer(current, index);
    Solution chain_best = current;
    double temperature = 0.05 * current.cost / std::max<std::size_t>(1, current.seq.size());
    // An iteration cap with a zero budget means "no time limit"; otherwise the budget always holds.
    for (std::uint64_t it = 0;; ++it) {
      if (o.max_iterations > 0 && it >= o.max_iterations) break;
      if (timed && elapsed() >= o.budget_seconds) break;
      if (o.stop != nullptr && o.stop->load()) break;
      Solution trial = (it % 200 == 199) ? chain_best : current;  // return to the best now and then
      chain.destroy(trial);
      if (chain.rng().uniform01() < 0.5) {
        chain.repair(trial, chain.rng().uniform01());
      } else {
        chain.repair_by_target(trial, chain.rng().uniform01());
      }
      chain.local_search(trial);
      ++iterations;
      if (trial.cost < current.cost - kEps ||
          chain.rng().uniform01() < std::exp(-(trial.cost - current.cost) / std::max(temperature, 1e-12))) {
        current = std::move(trial);
      }
      if (current.cost < chain_best.cost - kEps) {
        chain_best = current;
        offer(chain_best, index);
      }
      temperature *= 0.9995;
    }
  };
  const auto run_chain = [&](std::size_t index) {
    try {
      search_chain(index);
    } catch (const ClosureStopped&) {
      // stopped while a distance row was missing: the best tour offered so far stands
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(run_chain, t);
  run_chain(0);
  for (auto& t : pool) t.join();

  result.iterations = iterations;
  result.distance_rows = c.rows();
  finish_bound();
  if (best.seq.empty() && !quick) {
    throw std::runtime_error(fmt::format("tour: stopped before a first tour was found ({} of {} distance rows computed)",
                                         c.rows(), c.n));
  }
  result.tour = best.seq.empty() ? *quick : expand(g, c, best.seq);
  result.tour.covered.clear();
  std::vector<char> seen(g.poi_count(), 0);
  for (const VertexId v : result.tour.walk) {
    for (const PoiId p : g.visible(v)) seen[p] = 1;
  }
  for (const PoiId p : result.targets) {
    if (seen[p]) result.tour.covered.push_back(p);
  }
  result.validation = validate_tour(g, o.root, result.targets, result.tour);
  result.seconds = elapsed();
  return result;
}

}  // namespace ispars
