#pragma once
// The graph inspection problem on the metric closure of candidate viewpoints, for the tour
// solver: candidate 0 is the root, every other candidate is a vertex of the root's component
// that sees a target, and the distance between two candidates is their shortest-path length in
// the graph. Distances come a row at a time (one Dijkstra from a candidate, ended once every
// candidate is settled, so its entries are exact): all rows ahead of the search when the
// candidates are few, otherwise a row on first use (a tour vertex's row answers every distance
// the search asks of it). Memory is rows x candidates, never n^2 over
// the graph. Above `max_candidates` the candidates are thinned: every target keeps its first k
// viewers by each of three rankings (most targets seen; nearest the root; nearest an anchor, the
// root or a target's richest or nearest viewer), with the largest k that fits. Thinning can
// lengthen the best tour the search can find; it never touches `simple_bound`, which is taken
// over every viewer before thinning.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::planning {

/// Thrown by TourClosure::d() when a row is needed after the caller asked to stop.
struct ClosureStopped : std::runtime_error {
  ClosureStopped() : std::runtime_error("stopped while computing distances") {}
};

struct TourClosureOptions {
  unsigned threads = 1;                   ///< For the rows computed ahead.
  std::size_t max_candidates = 8000;      ///< Above this, thin the candidates.
  std::size_t rows_ahead_up_to = 3000;    ///< Compute every row ahead when there are at most this many.
  std::function<bool()> should_stop;      ///< Refuses lazy rows (ClosureStopped) and stops rows ahead.
  std::function<bool()> stop_rows_ahead;  ///< Stops rows ahead only (a budget): the rest come on first use.
};

class TourClosure {
 public:
  TourClosure(const InspectionGraph& graph, VertexId root, const std::vector<PoiId>& targets,
              const std::vector<VertexId>& component, const TourClosureOptions& options);

  /// Shortest-path length between candidates a and b (symmetric; computes a row if neither has
  /// one yet; throws ClosureStopped if that is needed after should_stop()). Safe from many threads.
  [[nodiscard]] double d(std::size_t a, std::size_t b) const {
    if (complete_) return matrix_[a * n + b];  // the search's hot path: one load, no atomics
    if (const double* r = rows_[a].load(std::memory_order_acquire)) return r[b];
    if (const double* r = rows_[b].load(std::memory_order_acquire)) return r[a];
    return row(a)[b];
  }

  /// Computes candidate a's row now if it has none: the search calls this for every vertex it
  /// puts in a tour, so that d(tour vertex, anything) never needs another row.
  void ensure_row(std::size_t a) const {
    if (!complete_ && rows_[a].load(std::memory_order_acquire) == nullptr) (void)row(a);
  }

  std::size_t n = 0;                                ///< Candidates.
  std::vector<VertexId> vertex;                     ///< candidate -> graph vertex
  std::vector<std::vector<std::uint32_t>> sees;     ///< candidate -> local target ids, ascending
  std::vector<std::vector<std::uint32_t>> seen_by;  ///< local target -> candidates, ascending
  std::size_t thinned = 0;                          ///< Viewers left out by thinning.
  /// Proven lower bound on every tour from the root that sees every target: the largest, over
  /// targets, of the cheapest round trip from the root to a vertex of the component seeing it,
  /// over all such vertices (computed before thinning, with one Dijkstra from the root).
  double simple_bound = 0.0;

  /// Rows computed so far.
  [[nodiscard]] std::size_t rows() const { return row_count_.load(); }

 private:
  // The constructor's steps: the candidates and what each sees, thinning to `kept`, the tables
  // over the candidates, and every row computed ahead (on options.threads threads).
  void collect_candidates(VertexId root, const std::vector<PoiId>& targets, const std::vector<VertexId>& component);
  void keep_candidates(const std::vector<std::size_t>& kept);
  void index_candidates(std::size_t target_count);
  void compute_rows_ahead(const TourClosureOptions& options);
  const double* row(std::size_t a) const;
  void compute_row(std::size_t a, std::vector<double>& scratch) const;

  const InspectionGraph* graph_;
  std::function<bool()> should_stop_;
  std::vector<char> is_candidate_;  // graph vertex -> 1 when a candidate: a row's search ends once all are settled
  std::unique_ptr<std::atomic<const double*>[]> rows_;
  mutable std::vector<std::unique_ptr<double[]>> storage_;  // lazy rows
  // Rows computed ahead live in one n x n block; when every row is there, d() reads it directly.
  std::unique_ptr<double[]> matrix_;
  bool complete_ = false;
  mutable std::mutex mutex_;
  mutable std::atomic<std::size_t> row_count_{0};
};

}  // namespace ispars::planning
