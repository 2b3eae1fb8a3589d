#include "ispars/planning/tour/gip_solver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <optional>
#include <thread>

#include "gip_search.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/search/graph_search.hpp"
#include "ispars/planning/tour/quick_tour.hpp"
#include "ispars/planning/tour/tour_bound.hpp"
#include "ispars/planning/tour/tour_closure.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

using Clock = std::chrono::steady_clock;
using gip_search::Chain;
using gip_search::Closure;
using gip_search::kEps;
using gip_search::kInf;
using gip_search::Solution;
// With rows on first use, the first tour is built from each target's this many richest viewers.
constexpr std::size_t kFirstTourViewers = 1;
constexpr std::uint32_t kNotCandidate = std::numeric_limits<std::uint32_t>::max();

// Dijkstra from `source` (graph_search.hpp), ending once `stop_at` is settled.
void dijkstra_to(const InspectionGraph& g, VertexId source, std::vector<double>& dist, std::vector<VertexId>* parent,
                 VertexId stop_at = kNoVertex) {
  const SearchSource from{source, 0.0};
  dijkstra(g, std::span<const SearchSource>(&from, 1), dist, parent, [stop_at](VertexId v) { return v == stop_at; });
}

std::vector<PoiId> choose_targets(const InspectionGraph& g, const GipOptions& o,
                                  const std::vector<VertexId>& component) {
  std::vector<char> seen(g.poi_count(), 0);
  for (const VertexId v : component) {
    for (const PoiId p : g.visible(v)) seen[p] = 1;
  }
  std::vector<PoiId> targets;
  if (!o.targets) {
    for (PoiId p = 0; p < g.poi_count(); ++p) {
      if (seen[p]) targets.push_back(p);
    }
    if (targets.empty()) throw params::InputError("tour", "targets", "no POI is seen from the root's component");
    return targets;
  }
  targets = *o.targets;
  std::sort(targets.begin(), targets.end());
  targets.erase(std::unique(targets.begin(), targets.end()), targets.end());
  if (targets.empty()) throw params::InputError("tour", "targets", "the target set is empty");
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
    throw params::InputError("tour", "targets",
                             fmt::format("{} unknown POI ids (the first: {}; the graph has POIs 0..{})", unknown,
                                         first_unknown, g.poi_count() == 0 ? 0 : g.poi_count() - 1));
  }
  if (unreachable > 0) {
    throw params::InputError("tour", "targets",
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

// The root and budget checked; a root with no edges refused unless it sees every target itself.
void check_options(const InspectionGraph& g, const GipOptions& o) {
  if (o.root >= g.vertex_count()) {
    throw params::InputError("tour", "root",
                             fmt::format("vertex {} is not in the graph ({} vertices)", o.root, g.vertex_count()));
  }
  if (!(o.budget_seconds >= 0.0) || !std::isfinite(o.budget_seconds)) {
    throw params::InputError("tour", "budget",
                             fmt::format("must be a finite number of seconds >= 0, got {}", o.budget_seconds));
  }
  for (const VertexId v : o.initial_walk) {
    if (v >= g.vertex_count()) {
      throw params::InputError("tour", "initial_walk",
                               fmt::format("vertex {} is not in the graph ({} vertices)", v, g.vertex_count()));
    }
  }
  if (!g.neighbors(o.root).empty()) return;
  const auto sees = g.visible(o.root);
  const bool root_suffices =
      o.targets
          ? !o.targets->empty() && std::all_of(o.targets->begin(), o.targets->end(),
                                               [&](PoiId p) { return std::binary_search(sees.begin(), sees.end(), p); })
          : !sees.empty();
  if (!root_suffices) {
    throw params::InputError("tour", "root",
                             fmt::format("the root (vertex {}) has no edges: no tour can leave it", o.root));
  }
}

// One solve: the LP bound on a thread of its own beside the search, a quick first tour on large
// instances, the search chains over the closure, and the result assembled at the end.
class GipRun {
 public:
  GipRun(const InspectionGraph& g, const GipOptions& o) : g_(g), o_(o) {}
  ~GipRun() {  // if the search throws, the bounding thread is stopped and joined anyway
    abandon_bound_ = true;
    if (bound_thread_.joinable()) bound_thread_.join();
  }
  GipRun(const GipRun&) = delete;
  GipRun& operator=(const GipRun&) = delete;

  GipResult solve() {
    const std::vector<VertexId> component = g_.component_of(o_.root);
    result_.targets = choose_targets(g_, o_, component);
    if (root_sees_every_target()) return staying_at_the_root();
    start_bound();
    // A quick first tour (a walk to the nearest unseen viewpoints) before the search, on every
    // graph: it is in hand within milliseconds, where the closure's rows take tenths of a second;
    // the search's tours replace it as soon as they beat it.
    quick_ = nearest_viewpoint_tour(g_, o_.root, result_.targets, o_.stop);
    if (quick_) improved(quick_->cost);
    const Closure c(g_, o_.root, result_.targets, component, closure_options());
    result_.thinned = c.thinned;
    result_.candidates = c.n;
    result_.lower_bound = c.simple_bound;  // over every viewer (thinning never touches it; tour_closure.hpp)
    search(c);
    result_.distance_rows = c.rows();
    finish_bound();
    if (best_.seq.empty() && !quick_) {
      throw std::runtime_error(
          fmt::format("tour: stopped before a first tour was found ({} of {} distance rows computed)", c.rows(), c.n));
    }
    result_.tour = best_.seq.empty() ? *quick_ : expand(g_, c, best_.seq);
    return finish();
  }

 private:
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }
  bool timed() const { return o_.max_iterations == 0 || o_.budget_seconds > 0; }

  bool root_sees_every_target() const {
    const auto sees = g_.visible(o_.root);
    return std::all_of(result_.targets.begin(), result_.targets.end(),
                       [&](PoiId p) { return std::binary_search(sees.begin(), sees.end(), p); });
  }
  GipResult staying_at_the_root() {
    result_.tour.walk = {o_.root};
    result_.tour.covered = result_.targets;
    result_.trace.push_back({elapsed(), 0.0});
    result_.lower_bound = 0.0;
    result_.candidates = 1;
    result_.validation = validate_tour(g_, o_.root, result_.targets, result_.tour);
    result_.seconds = elapsed();
    return std::move(result_);
  }

  void improved(double cost) {  // called with mutex_ held, or before the chains start
    result_.trace.push_back({elapsed(), cost});
    if (o_.on_improvement) o_.on_improvement(result_.trace.back().first, cost);
  }

  // The LP bound runs beside the search on its own thread, until the search ends.
  void start_bound() {
    if (!o_.lp_bound) return;
    TourBoundOptions bo;
    bo.root = o_.root;
    bo.targets = result_.targets;
    bo.budget_seconds = o_.bound_seconds > 0.0 ? o_.bound_seconds : o_.budget_seconds > 0.0 ? o_.budget_seconds : 1e7;
    bo.should_stop = [this] { return abandon_bound_.load() || (o_.stop != nullptr && o_.stop->load()); };
    const double offset = elapsed();
    bo.on_improvement = [this, offset](double seconds, double bound) {
      std::lock_guard lock(bound_mutex_);
      result_.bound_trace.emplace_back(offset + seconds, bound);
      if (o_.on_bound) o_.on_bound(offset + seconds, bound);
    };
    bound_thread_ = std::thread([this, bo] { bounded_ = lp_tour_bound(g_, bo); });
  }
  void finish_bound() {
    if (o_.bound_seconds <= 0.0 && o_.budget_seconds <= 0.0) abandon_bound_ = true;  // no budget of its own
    if (bound_thread_.joinable()) bound_thread_.join();
    result_.lower_bound = std::max(result_.lower_bound.value_or(0.0), bounded_.bound);
    result_.bound_complete = bounded_.complete;
    result_.bound_rounds = bounded_.rounds;
    result_.bound_cuts = bounded_.cuts;
    result_.bound_dropped = bounded_.dropped;
    result_.bound_peak_nonzeros = bounded_.peak_nonzeros;
    result_.bound_note = bounded_.skipped;
  }

  TourClosureOptions closure_options() const {
    TourClosureOptions co;
    co.threads = std::max(1u, o_.threads);
    // Rows ahead stop at the budget (the rest come on first use). A lazy row is refused after a
    // stop, and, with a quick tour in hand, past the budget too.
    co.should_stop = [this] {
      return (o_.stop != nullptr && o_.stop->load()) || (quick_ && timed() && elapsed() >= o_.budget_seconds);
    };
    co.stop_rows_ahead = [this] { return timed() && elapsed() >= o_.budget_seconds; };
    return co;
  }

  void offer(const Solution& s, std::size_t chain) {
    std::lock_guard lock(mutex_);
    const bool better = s.cost < best_.cost - kEps;
    if (better || (std::abs(s.cost - best_.cost) <= kEps && chain < best_chain_)) {
      best_ = s;
      best_chain_ = chain;
      if (better) improved(s.cost);
    }
  }

  // One chain: a greedy first tour, local search, then destroy/repair with annealing.
  void search_chain(const Closure& c, std::size_t index, const std::vector<char>* first_pool) {
    Chain chain(c, o_.seed * 0x9E3779B97F4A7C15ull + index + 1);
    Solution current = index == 0 && !o_.initial_walk.empty() ? chain.through(initial_candidates(c)) : chain.empty();
    chain.repair(current, index == 0 ? 0.0 : 0.3, first_pool);
    chain.local_search(current);
    offer(current, index);
    Solution chain_best = current;
    double temperature = 0.05 * current.cost / std::max<std::size_t>(1, current.seq.size());
    // An iteration cap with a zero budget means "no time limit"; otherwise the budget always holds.
    for (std::uint64_t it = 0;; ++it) {
      if (o_.max_iterations > 0 && it >= o_.max_iterations) break;
      if (timed() && elapsed() >= o_.budget_seconds) break;
      if (o_.stop != nullptr && o_.stop->load()) break;
      Solution trial = (it % 200 == 199) ? chain_best : current;  // return to the best now and then
      chain.destroy(trial);
      if (chain.rng().uniform01() < 0.5) {
        chain.repair(trial, chain.rng().uniform01());
      } else {
        chain.repair_by_target(trial, chain.rng().uniform01());
      }
      chain.local_search(trial);
      ++iterations_;
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
  }

  // The candidates the initial walk passes, in walk order (the root's candidate is 0).
  std::vector<std::uint32_t> initial_candidates(const Closure& c) const {
    std::vector<std::uint32_t> of_vertex(g_.vertex_count(), kNotCandidate);
    for (std::uint32_t i = 0; i < c.n; ++i) of_vertex[c.vertex[i]] = i;
    std::vector<std::uint32_t> out;
    for (const VertexId v : o_.initial_walk) {
      if (v < of_vertex.size() && of_vertex[v] != kNotCandidate && of_vertex[v] != 0) out.push_back(of_vertex[v]);
    }
    return out;
  }

  void search(const Closure& c) {
    best_.cost = quick_ ? quick_->cost : kInf;  // a search tour is offered only when it beats the quick one
    // When rows come on first use (each a Dijkstra over the graph, about 0.1 s at 5.7 M edges),
    // every stop of the first tour costs one: it is built from the richest viewers alone, which
    // need few stops. Later repairs draw on every candidate.
    const std::vector<char> first_pool =
        c.rows() < c.n ? gip_search::richest_viewers(c, kFirstTourViewers) : std::vector<char>{};
    const auto run_chain = [&](std::size_t index) {
      try {
        search_chain(c, index, first_pool.empty() ? nullptr : &first_pool);
      } catch (const ClosureStopped&) {
        // stopped while a distance row was missing: the best tour offered so far stands
      }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < std::max(1u, o_.threads); ++t) pool.emplace_back(run_chain, t);
    run_chain(0);
    for (auto& t : pool) t.join();
    result_.iterations = iterations_;
  }

  GipResult finish() {
    result_.tour.covered.clear();
    std::vector<char> seen(g_.poi_count(), 0);
    for (const VertexId v : result_.tour.walk) {
      for (const PoiId p : g_.visible(v)) seen[p] = 1;
    }
    for (const PoiId p : result_.targets) {
      if (seen[p]) result_.tour.covered.push_back(p);
    }
    result_.validation = validate_tour(g_, o_.root, result_.targets, result_.tour);
    result_.seconds = elapsed();
    return std::move(result_);
  }

  const InspectionGraph& g_;
  const GipOptions& o_;
  const Clock::time_point t0_ = Clock::now();
  GipResult result_;
  std::optional<InspectionTour> quick_;
  std::atomic<bool> abandon_bound_{false};  // set when the search fails, or ends with no bound budget
  std::mutex bound_mutex_;
  TourBoundResult bounded_;
  std::thread bound_thread_;
  std::mutex mutex_;  // the best tour and the trace
  Solution best_;
  std::size_t best_chain_ = 0;
  std::atomic<std::uint64_t> iterations_{0};
};

}  // namespace

GipResult solve_gip(const InspectionGraph& g, const GipOptions& o) {
  check_options(g, o);
  GipRun run(g, o);
  return run.solve();
}

}  // namespace ispars::planning
