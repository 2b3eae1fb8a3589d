#include "ispars/tour/gip_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>

#include "ispars/search/graph_search.hpp"
#include "ispars/input_error.hpp"
#include "ispars/geometry/random.hpp"
#include "ispars/tour/quick_tour.hpp"
#include "ispars/tour/tour_bound.hpp"
#include "ispars/tour/tour_closure.hpp"
#include "gip_search.hpp"

namespace ispars {
namespace {

using Clock = std::chrono::steady_clock;
using gip_search::Chain;
using gip_search::Closure;
using gip_search::kEps;
using gip_search::kInf;
using gip_search::Solution;
// Above this many vertices in the root's component, a quick first tour comes before the search.
constexpr std::size_t kQuickTourAbove = 20'000;
// With rows on first use, the first tour is built from each target's this many richest viewers.
constexpr std::size_t kFirstTourViewers = 1;

// Dijkstra from `source` (graph_search.hpp), ending once `stop_at` is settled.
void dijkstra_to(const InspectionGraph& g, VertexId source, std::vector<double>& dist, std::vector<VertexId>* parent,
                 VertexId stop_at = kNoVertex) {
  const SearchSource from{source, 0.0};
  dijkstra(g, std::span<const SearchSource>(&from, 1), dist, parent, [stop_at](VertexId v) { return v == stop_at; });
}

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
    dijkstra_to(g, a, dist, &parent, b);
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

  // The simple bound, over every viewer (thinning never touches it; tour_closure.hpp).
  result.lower_bound = c.simple_bound;

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
  // When rows come on first use (each a Dijkstra over the whole graph, about 0.2 s at 5.7 M
  // edges), every stop of the first tour costs one: it is built from the richest viewers alone,
  // which need few stops. Later repairs draw on every candidate.
  const std::vector<char> first_pool = c.rows() < c.n ? gip_search::richest_viewers(c, kFirstTourViewers)
                                                       : std::vector<char>{};
  const auto search_chain = [&](std::size_t index) {
    Chain chain(c, o.seed * 0x9E3779B97F4A7C15ull + index + 1);
    Solution current = chain.empty();
    chain.repair(current, index == 0 ? 0.0 : 0.3, first_pool.empty() ? nullptr : &first_pool);
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
