#include "ispars/planning/tour/tour_bound.hpp"

#include <fmt/format.h>
#include <ClpEventHandler.hpp>
#include <ClpSimplex.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "ispars/planning/tour/cut_separation.hpp"

namespace ispars::planning {
namespace {

using Clock = std::chrono::steady_clock;

// Stops Clp between iterations when the caller's stop flag is set or the deadline passes.
class StopHandler final : public ClpEventHandler {
 public:
  StopHandler(const std::function<bool()>* stop, Clock::time_point deadline) : stop_(stop), deadline_(deadline) {}
  int event(Event which) override {
    if (which != endOfIteration) return -1;
    if ((*stop_ && (*stop_)()) || Clock::now() >= deadline_) return 0;
    return -1;
  }
  ClpEventHandler* clone() const override { return new StopHandler(*this); }

 private:
  const std::function<bool()>* stop_;
  Clock::time_point deadline_;
};

// The cut x(delta(S)) >= 2 as the sorted columns of the edges leaving S.
std::vector<int> cut_columns(const CutGraph& g, const std::vector<char>& in_s) {
  std::vector<int> columns;
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    if (in_s[g.edges[e].first] != in_s[g.edges[e].second]) columns.push_back(static_cast<int>(e));
  }
  return columns;
}

std::uint64_t signature(const std::vector<int>& columns) {
  std::uint64_t h = 1469598103934665603ull;
  for (const int c : columns) h = (h ^ static_cast<std::uint64_t>(c)) * 1099511628211ull;
  return h ^ columns.size();
}

// A bound that the dual y proves exactly: with y clipped to >= 0 and scaled by lambda so that
// every reduced cost is >= 0, lambda * 2 * sum(y) is a dual objective, hence a lower bound.
double proven_bound(const ClpSimplex& lp, const std::vector<double>& costs) {
  const int rows = lp.numberRows();
  const double* dual = lp.dualRowSolution();
  std::vector<double> load(costs.size(), 0.0);
  const CoinPackedMatrix* m = lp.matrix();
  const int* index = m->getIndices();
  const CoinBigIndex* start = m->getVectorStarts();
  const int* length = m->getVectorLengths();
  double value = 0.0;
  std::vector<double> y(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    y[r] = std::max(0.0, dual[r]);
    value += 2.0 * y[r];
  }
  // Column-major matrix: column j's rows are index[start[j] .. start[j] + length[j]).
  double lambda = 1.0;
  for (std::size_t j = 0; j < costs.size(); ++j) {
    double a = 0.0;
    for (CoinBigIndex k = start[j]; k < start[j] + length[j]; ++k) a += y[index[k]];
    if (a > costs[j]) lambda = std::min(lambda, costs[j] / a);
  }
  return std::max(0.0, lambda * value * (1.0 - 1e-9));
}

// Drops the rows whose dual is 0 (the LP's optimum stays: its dual stays feasible with the same
// objective) and forgets their signatures, so that a cut violated again later is added again.
std::size_t drop_idle_cuts(ClpSimplex& lp, std::vector<std::uint64_t>& row_signature,
                           std::unordered_set<std::uint64_t>& known) {
  const double* dual = lp.dualRowSolution();
  std::vector<int> idle;
  std::vector<std::uint64_t> kept;
  for (int r = 0; r < lp.numberRows(); ++r) {
    if (std::abs(dual[r]) <= 1e-12) {
      idle.push_back(r);
      known.erase(row_signature[static_cast<std::size_t>(r)]);
    } else {
      kept.push_back(row_signature[static_cast<std::size_t>(r)]);
    }
  }
  if (!idle.empty()) lp.deleteRows(static_cast<int>(idle.size()), idle.data());
  row_signature = std::move(kept);
  return idle.size();
}

// The LP's cut rows: each cut queued once (by its signature) and added in rounds, within a cap
// on the LP's nonzeros.
class CutRows {
 public:
  CutRows(const CutGraph& g, std::size_t max_nonzeros) : g_(g), max_nonzeros_(max_nonzeros) {}

  // Queues the cut of S = {v : in_s[v]}, unless it is empty, known, or past the cap (then full).
  void queue(const ClpSimplex& lp, const std::vector<char>& in_s) {
    std::vector<int> columns = cut_columns(g_, in_s);
    if (columns.empty()) return;
    if (static_cast<std::size_t>(lp.getNumElements()) + columns_.size() + columns.size() > max_nonzeros_) {
      full = true;
      return;
    }
    const std::uint64_t sig = signature(columns);
    if (!known_.insert(sig).second) return;
    row_signature_.push_back(sig);
    columns_.insert(columns_.end(), columns.begin(), columns.end());
    starts_.push_back(static_cast<int>(columns_.size()));
  }

  // Adds the queued cuts to `lp` (each: the edges across it carry at least 2); how many.
  int flush(ClpSimplex& lp, TourBoundResult& result) {
    const int added = static_cast<int>(starts_.size()) - 1;
    if (added > 0) {
      const std::vector<double> row_lower(static_cast<std::size_t>(added), 2.0);
      const std::vector<double> row_upper(static_cast<std::size_t>(added), COIN_DBL_MAX);
      const std::vector<double> ones(columns_.size(), 1.0);
      lp.addRows(added, row_lower.data(), row_upper.data(), starts_.data(), columns_.data(), ones.data());
      result.cuts += static_cast<std::size_t>(added);
      result.peak_nonzeros = std::max(result.peak_nonzeros, static_cast<std::size_t>(lp.getNumElements()));
    }
    starts_.assign(1, 0);
    columns_.clear();
    return added;
  }

  // Drops the cuts that do not bind; how many.
  std::size_t drop_idle(ClpSimplex& lp) { return drop_idle_cuts(lp, row_signature_, known_); }

  bool full = false;  ///< this round's cuts reached the cap

 private:
  const CutGraph& g_;
  std::size_t max_nonzeros_;
  std::unordered_set<std::uint64_t> known_;
  std::vector<std::uint64_t> row_signature_;  // of each LP row, in row order
  std::vector<int> starts_{0}, columns_;
};

}  // namespace

TourBoundResult lp_tour_bound(const InspectionGraph& graph, const TourBoundOptions& o) {
  const auto t0 = Clock::now();
  const auto deadline = t0 + std::chrono::duration_cast<Clock::duration>(
                                 std::chrono::duration<double>(std::max(0.0, std::min(o.budget_seconds, 1e7))));
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  const auto stopped = [&] { return (o.should_stop && o.should_stop()) || Clock::now() >= deadline; };
  TourBoundResult result;

  if (graph.edge_count() > o.max_edges) {  // checked before copying anything
    result.skipped =
        fmt::format("the graph has {} edges, more than the LP's limit of {}", graph.edge_count(), o.max_edges);
    return result;
  }
  const CutGraph g = CutGraph::of_component(graph, o.root, o.targets);
  if (g.groups.empty()) {
    result.complete = true;  // the root sees every target: the empty tour is optimal
    return result;
  }

  ClpSimplex lp;
  lp.setLogLevel(0);
  StopHandler handler(&o.should_stop, deadline);
  lp.passInEventHandler(&handler);
  std::vector<double> costs(g.edges.size());
  for (std::size_t e = 0; e < g.edges.size(); ++e) costs[e] = g.costs[e];
  const std::vector<double> lower(costs.size(), 0.0), upper(costs.size(), COIN_DBL_MAX);
  lp.addColumns(static_cast<int>(costs.size()), lower.data(), upper.data(), costs.data(), nullptr, nullptr, nullptr);

  CutRows rows(g, o.max_cut_nonzeros);
  // Start from the cut around the root and the cut around each group.
  std::vector<char> in_s(g.vertex_count, 0);
  in_s[g.root] = 1;
  rows.queue(lp, in_s);
  for (const auto& group : g.groups) {
    std::fill(in_s.begin(), in_s.end(), 1);
    for (const std::uint32_t v : group) in_s[v] = 0;
    rows.queue(lp, in_s);
  }
  rows.flush(lp, result);

  MaxFlow flow(g);
  while (!stopped()) {
    lp.dual();
    ++result.rounds;
    if (lp.status() != 0) break;  // stopped by the event handler, or numerically lost: keep what is proven
    const double bound = proven_bound(lp, costs);
    if (bound > result.bound) {
      result.bound = bound;
      result.trace.emplace_back(elapsed(), bound);
      if (o.on_improvement) o.on_improvement(elapsed(), bound);
    }
    // Past half the cap, the cuts that do not bind make room for new ones.
    if (static_cast<std::size_t>(lp.getNumElements()) > o.max_cut_nonzeros / 2) {
      result.dropped += rows.drop_idle(lp);
    }
    rows.full = false;
    // Separation: a group the root sends less than 2 units of flow to, on capacities x.
    flow.set_capacities(lp.primalColumnSolution());
    for (const auto& group : g.groups) {
      if (stopped()) break;
      if (flow.max_flow_to(group, 2.0) >= 2.0 - 1e-6) continue;
      rows.queue(lp, flow.source_side());
      rows.queue(lp, flow.sink_side_complement());
    }
    if (stopped()) break;
    if (rows.flush(lp, result) == 0) {
      result.complete = !rows.full;
      result.capped = rows.full;  // the cuts that bind fill the cap: the bound stands as proven
      break;
    }
  }
  result.seconds = elapsed();
  return result;
}

}  // namespace ispars::planning
