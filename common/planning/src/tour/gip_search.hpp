// The search moves of the GIP solver (gip_solver.cpp): a tour on the metric closure of the
// candidate viewpoints and one search chain (randomized greedy construction, local search, and
// large-neighbourhood destroy/repair). Private to the solver; one chain per search thread.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "ispars/planning/tour/tour_closure.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning::gip_search {
// Internal linkage: one translation unit (gip_solver.cpp) uses this, and the compiler inlines
// the search's small helpers into their callers far more readily than for external ones.
namespace {

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kEps = 1e-9;
using Closure = TourClosure;

// A tour on the closure: seq[0] is the root; the tour closes back to it.
struct Solution {
  std::vector<std::uint32_t> seq;
  std::vector<std::uint32_t> count;  // per target: tour vertices seeing it
  std::vector<char> in_tour;         // per candidate
  double cost = 0.0;
  std::size_t uncovered = 0;
};

// The candidates among every target's `k` richest viewers (most targets seen; ties: lowest
// index). A first tour built from these alone needs few stops, hence few distance rows, when rows
// come on first use (each a Dijkstra over the whole graph).
inline std::vector<char> richest_viewers(const Closure& c, std::size_t k) {
  std::vector<char> pool(c.n, 0);
  std::vector<std::uint32_t> viewers;
  for (const auto& seen_by : c.seen_by) {
    viewers = seen_by;
    const std::size_t keep = std::min(k, viewers.size());
    std::partial_sort(viewers.begin(), viewers.begin() + static_cast<std::ptrdiff_t>(keep), viewers.end(),
                      [&](std::uint32_t a, std::uint32_t b) {
                        return c.sees[a].size() != c.sees[b].size() ? c.sees[a].size() > c.sees[b].size() : a < b;
                      });
    for (std::size_t i = 0; i < keep; ++i) pool[viewers[i]] = 1;
  }
  return pool;
}

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

  // The tour through `candidates` in their order (the root first, each once), not yet searched:
  // a warm start. Its cost is the closure's, never above the walk's it came from.
  Solution through(const std::vector<std::uint32_t>& candidates) const {
    Solution s = empty();
    for (const std::uint32_t v : candidates) {
      if (s.in_tour[v]) continue;
      const std::size_t last = s.seq.size() - 1;
      insert(s, v, last, c_.d(s.seq[last], v) + c_.d(v, s.seq[0]) - c_.d(s.seq[last], s.seq[0]));
    }
    s.cost = tour_cost(s.seq);
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
  // every target is seen; `noise` randomises the choice. With `pool`, only candidates it marks
  // are inserted (it must hold a viewer of every target).
  void repair(Solution& s, double noise, const std::vector<char>* pool = nullptr) {
    std::vector<std::uint32_t> gain(c_.n, 0);
    std::vector<std::uint32_t> touched;
    while (s.uncovered > 0) {
      touched.clear();
      for (std::size_t t = 0; t < s.count.size(); ++t) {
        if (s.count[t] != 0) continue;
        for (const auto v : c_.seen_by[t]) {
          if (s.in_tour[v] || (pool != nullptr && !(*pool)[v])) continue;
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
        const double saving =
            c_.d(s.seq[i - 1], v) + c_.d(v, s.seq[(i + 1) % m]) - c_.d(s.seq[i - 1], s.seq[(i + 1) % m]);
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
            std::reverse(s.seq.begin() + static_cast<std::ptrdiff_t>(i + 1),
                         s.seq.begin() + static_cast<std::ptrdiff_t>(j + 1));
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

  scene_files::Rng& rng() { return rng_; }

 private:
  const Closure& c_;
  scene_files::Rng rng_;
};

}  // namespace
}  // namespace ispars::planning::gip_search
