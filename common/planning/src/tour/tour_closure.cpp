#include "ispars/planning/tour/tour_closure.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <thread>

#include "ispars/planning/search/graph_search.hpp"

namespace ispars::planning {
namespace {

constexpr double kNoRoute = std::numeric_limits<double>::infinity();

// The candidates' order under each of thinning's three rankings: richest first (most targets
// seen); nearest the root first; nearest an anchor first (the root, and every target's richest
// and nearest viewers: the cheapest detours from where a tour goes anyway). Ties: lowest index.
std::vector<std::vector<std::size_t>> rankings(const InspectionGraph& graph, const std::vector<VertexId>& vertex,
                                               const std::vector<std::vector<std::uint32_t>>& sees, std::size_t targets,
                                               const std::vector<double>& from_root,
                                               const std::function<bool(VertexId)>& stopped) {
  std::vector<std::size_t> order(vertex.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto ranked = [&](const auto& before) {
    std::vector<std::size_t> r = order;
    std::stable_sort(r.begin() + 1, r.end(), before);  // the root stays first
    return r;
  };
  std::vector<std::vector<std::size_t>> out;
  out.push_back(ranked([&](std::size_t a, std::size_t b) { return sees[a].size() > sees[b].size(); }));
  out.push_back(ranked([&](std::size_t a, std::size_t b) { return from_root[vertex[a]] < from_root[vertex[b]]; }));
  // Anchors: the first viewer of every target in each of the two rankings so far.
  std::vector<SearchSource> anchors{{vertex[0], 0.0}};
  for (const auto& r : out) {
    std::vector<char> has(targets, 0);
    for (const std::size_t i : r) {
      bool first = false;
      for (const auto t : sees[i]) first = first || !has[t];
      if (!first) continue;
      for (const auto t : sees[i]) has[t] = 1;
      anchors.push_back({vertex[i], 0.0});
    }
  }
  std::vector<double> from_anchor;
  dijkstra(graph, std::span<const SearchSource>(anchors), from_anchor, nullptr, stopped);
  out.push_back(ranked([&](std::size_t a, std::size_t b) { return from_anchor[vertex[a]] < from_anchor[vertex[b]]; }));
  return out;
}

// Keeps, for every target and every ranking, its first k viewers in that ranking, with the
// largest k that stays within `limit` candidates (at least 1 per target and ranking).
std::vector<std::size_t> thin(const std::vector<std::vector<std::size_t>>& ranks,
                              const std::vector<std::vector<std::uint32_t>>& sees, std::size_t targets,
                              std::size_t limit) {
  const auto keep_with = [&](std::size_t k) {
    std::vector<char> keep(sees.size(), 0);
    keep[0] = 1;  // the root
    for (const auto& rank : ranks) {
      std::vector<std::size_t> taken(targets, 0);
      for (std::size_t r = 1; r < rank.size(); ++r) {
        bool wanted = false;
        for (const auto t : sees[rank[r]]) wanted = wanted || taken[t] < k;
        if (!wanted) continue;
        for (const auto t : sees[rank[r]]) ++taken[t];
        keep[rank[r]] = 1;
      }
    }
    std::vector<std::size_t> kept;
    for (std::size_t i = 0; i < keep.size(); ++i) {
      if (keep[i]) kept.push_back(i);
    }
    return kept;
  };
  std::size_t lo = 1, hi = 1;
  while (keep_with(hi * 2).size() <= limit && hi < sees.size()) hi *= 2;
  hi *= 2;
  while (hi - lo > 1) {  // largest k within the limit
    const std::size_t mid = (lo + hi) / 2;
    (keep_with(mid).size() <= limit ? lo : hi) = mid;
  }
  return keep_with(lo);
}

}  // namespace

TourClosure::TourClosure(const InspectionGraph& graph, VertexId root, const std::vector<PoiId>& targets,
                         const std::vector<VertexId>& component, const TourClosureOptions& options)
    : graph_(&graph), should_stop_(options.should_stop) {
  collect_candidates(root, targets, component);
  // The simple bound, over every viewer (before any thinning): each target needs a round trip
  // from the root to some vertex that sees it.
  // These searches end early on should_stop() (checked every 4,096 settled vertices): a stopped
  // one gives no bound, and thinning by partial distances (the rows are refused anyway).
  bool was_stopped = false;
  std::size_t settled = 0;
  const std::function<bool(VertexId)> stopped = [&](VertexId) {
    if ((++settled & 4095) == 0 && should_stop_ && should_stop_()) was_stopped = true;
    return was_stopped;
  };
  std::vector<double> from_root;
  const SearchSource root_source{root, 0.0};
  dijkstra(graph, std::span<const SearchSource>(&root_source, 1), from_root, nullptr, stopped);
  std::vector<double> cheapest(targets.size(), kNoRoute);
  for (std::size_t i = 0; i < vertex.size(); ++i) {
    for (const auto t : sees[i]) cheapest[t] = std::min(cheapest[t], 2.0 * from_root[vertex[i]]);
  }
  for (const double c : cheapest) simple_bound = std::max(simple_bound, c);
  if (was_stopped) simple_bound = 0.0;  // distances past the stop are not shortest: no bound
  if (vertex.size() > options.max_candidates) {
    keep_candidates(thin(rankings(graph, vertex, sees, targets.size(), from_root, stopped), sees, targets.size(),
                         options.max_candidates));
  }
  index_candidates(targets.size());
  if (n > options.rows_ahead_up_to) {  // rows on first use; the root's is in hand already
    if (!was_stopped) {
      storage_[0] = std::make_unique<double[]>(n);
      for (std::size_t j = 0; j < n; ++j) storage_[0][j] = from_root[vertex[j]];
      rows_[0].store(storage_[0].get(), std::memory_order_release);
      ++row_count_;
    }
    return;
  }
  compute_rows_ahead(options);
}

void TourClosure::collect_candidates(VertexId root, const std::vector<PoiId>& targets,
                                     const std::vector<VertexId>& component) {
  // The root, then every vertex of the component that sees a target.
  const InspectionGraph& graph = *graph_;
  std::vector<std::int64_t> local(graph.poi_count(), -1);
  for (std::size_t t = 0; t < targets.size(); ++t) local[targets[t]] = static_cast<std::int64_t>(t);
  vertex.push_back(root);
  for (const VertexId v : component) {
    if (v == root) continue;
    for (const PoiId p : graph.visible(v)) {
      if (local[p] >= 0) {
        vertex.push_back(v);
        break;
      }
    }
  }
  sees.resize(vertex.size());
  for (std::size_t i = 0; i < vertex.size(); ++i) {
    for (const PoiId p : graph.visible(vertex[i])) {
      if (local[p] >= 0) sees[i].push_back(static_cast<std::uint32_t>(local[p]));
    }
    std::sort(sees[i].begin(), sees[i].end());
  }
}

void TourClosure::keep_candidates(const std::vector<std::size_t>& kept) {
  thinned = vertex.size() - kept.size();
  std::vector<VertexId> kept_vertex;
  std::vector<std::vector<std::uint32_t>> kept_sees;
  for (const std::size_t i : kept) {
    kept_vertex.push_back(vertex[i]);
    kept_sees.push_back(std::move(sees[i]));
  }
  vertex = std::move(kept_vertex);
  sees = std::move(kept_sees);
}

void TourClosure::index_candidates(std::size_t target_count) {
  n = vertex.size();
  is_candidate_.assign(graph_->vertex_count(), 0);
  for (const VertexId v : vertex) is_candidate_[v] = 1;
  seen_by.resize(target_count);
  for (std::size_t i = 0; i < n; ++i) {
    for (const auto t : sees[i]) seen_by[t].push_back(static_cast<std::uint32_t>(i));
  }
  rows_ = std::make_unique<std::atomic<const double*>[]>(n);
  for (std::size_t i = 0; i < n; ++i) rows_[i].store(nullptr);
  storage_.resize(n);
}

void TourClosure::compute_rows_ahead(const TourClosureOptions& options) {
  matrix_ = std::make_unique<double[]>(n * n);
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    std::vector<double> scratch;
    for (std::size_t i; (i = next++) < n;) {
      if ((should_stop_ && should_stop_()) || (options.stop_rows_ahead && options.stop_rows_ahead())) {
        return;  // the rest come on first use
      }
      compute_row(i, scratch);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < options.threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  complete_ = row_count_.load() == n;  // else stopped by the budget: the rest come on first use
}

const double* TourClosure::row(std::size_t a) const {
  std::lock_guard lock(mutex_);
  if (const double* r = rows_[a].load(std::memory_order_acquire)) return r;
  if (should_stop_ && should_stop_()) throw ClosureStopped();
  std::vector<double> scratch;
  compute_row(a, scratch);
  return rows_[a].load(std::memory_order_acquire);
}

void TourClosure::compute_row(std::size_t a, std::vector<double>& dist) const {
  // Dijkstra from candidate a, until every candidate is settled; only their entries are kept.
  const SearchSource from{vertex[a], 0.0};
  std::size_t found = 0;
  dijkstra(*graph_, std::span<const SearchSource>(&from, 1), dist, nullptr,
           [&](VertexId v) { return is_candidate_[v] && ++found == n; });
  double* values = nullptr;
  if (matrix_) {
    values = matrix_.get() + a * n;
  } else {
    storage_[a] = std::make_unique<double[]>(n);
    values = storage_[a].get();
  }
  for (std::size_t j = 0; j < n; ++j) values[j] = dist[vertex[j]];
  rows_[a].store(values, std::memory_order_release);
  ++row_count_;
}

}  // namespace ispars::planning
