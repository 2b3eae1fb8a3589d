// The spanner's rules that add sparse edges for path quality: Alg. 1, lines 24-26, Dobson &
// Bekris' shortcut test through the dense graph; then the sparse-vertex stretch rules.
//
// The stretch rules: Theorem 1's proof would bound the sparse route between two
// sparse viewpoints by t times the continuous route (its "sparse-endpoint refinement"); nothing in
// Alg. 1 enforces that between sparse vertices. Two rules do for nearby pairs, with the same t
// (no rule bounds a farther pair; docs/sparse-stretch.md):
// - vertex join: a new sparse vertex s takes an edge to each w in W(s) that it has no sparse
//   route to within t |s - w| (the direct segment is valid, so d_C(s, w) = |s - w|);
// - witnessed pairs: a sample q left out of G_s is a witness that w and w' of W(q) are at most
//   |w - q| + |q - w'| apart; a pair whose sparse route exceeds t times that is repaired.
// Both bounds take an additive slack (stretch_slack times Delta, 0 by default; from sample
// stretch_slack_after of the stream on, when that is set). With a positive
// slack each repair shortens its pair's route by more than the slack, so repairs thin out and
// the roadmap grows far more slowly (it still grows: docs/results/ispars2.md measures it). The
// slack is paid per bounded pair: a route made of k such hops may be k slacks longer.
// docs/sparse-stretch.md has the argument and the measurements.

#include <algorithm>
#include <cmath>
#include <span>

#include "ispars/planning/builders/spars_builder.hpp"

namespace ispars::planning {

void SparsBuilder::shortcut_test(VertexId q) {
  const VertexId v = rep_[q];
  if (v == kNoVertex || partners_[q].empty()) return;
  std::vector<ShortcutCandidate> candidates = shortcut_candidates(q, v);
  if (candidates.empty()) return;
  find_dense_supports(q, v, candidates);
  for (const ShortcutCandidate& c : candidates) {
    // This pair's sparse estimate against this pair's dense route (never another v''s).
    if (c.sparse_length > stretch_ * c.dense_length) {
      add_shortcut(q, v, c);
      return;
    }
  }
}

std::vector<SparsBuilder::ShortcutCandidate> SparsBuilder::shortcut_candidates(VertexId q, VertexId v) const {
  // Candidate (v', v''): q supports the interface v|v'; v'' is a sparse neighbour of v, not v'
  // and not adjacent to v', with a known interface v|v''. The sparse route between the two
  // interfaces through v is estimated with midpoints: (|v - v'| + |v - v''|) / 2.
  std::vector<ShortcutCandidate> candidates;
  std::vector<VertexId> around_v;
  around_v.assign(sparse_.neighbor_ids(v).begin(), sparse_.neighbor_ids(v).end());
  std::sort(around_v.begin(), around_v.end());
  const Vec3& pv = sparse_.position(v);
  for (const VertexId vp : partners_[q]) {
    for (const VertexId vpp : around_v) {
      if (vpp == vp || sparse_.has_edge(vp, vpp)) continue;
      const auto it = supports_[v].find(vpp);
      if (it == supports_[v].end() || it->second.empty()) continue;
      const double length = 0.5 * ((sparse_.position(vp) - pv).norm() + (sparse_.position(vpp) - pv).norm());
      candidates.push_back({vp, vpp, length});
    }
  }
  return candidates;
}

void SparsBuilder::find_dense_supports(VertexId q, VertexId v, std::vector<ShortcutCandidate>& candidates) {
  // One Dijkstra from q serves every candidate. A dense vertex x supports v|v'' when rep(x) = v
  // and v'' is among its partners; the first support settled is the nearest (ties: lowest id).
  // Only routes shorter than sparse_length / t can violate the stretch, so the search stops
  // once no pending candidate could still be violated, or none is pending.
  std::size_t pending = candidates.size();
  const auto pending_bound = [&] {
    double bound = 0.0;
    for (const ShortcutCandidate& c : candidates) {
      if (c.support == kNoVertex) bound = std::max(bound, c.sparse_length / stretch_);
    }
    return bound;
  };
  double bound = pending_bound();
  search_.start(dense_.graph().vertex_count(), q);
  while (pending > 0) {
    const auto [d, x] = search_.settle_next(dense_.graph(), bound);
    if (x == kNoVertex) break;
    if (rep_[x] != v) continue;
    bool resolved = false;
    for (ShortcutCandidate& c : candidates) {
      if (c.support == kNoVertex && std::binary_search(partners_[x].begin(), partners_[x].end(), c.vpp)) {
        c.dense_length = d;
        c.support = x;
        --pending;
        resolved = true;
      }
    }
    if (resolved) bound = pending_bound();
  }
}

void SparsBuilder::add_shortcut(VertexId q, VertexId v, const ShortcutCandidate& c) {
  ShortcutRecord record{v, c.vp, c.vpp, c.sparse_length, c.dense_length, false, {}, kNoVertex, kNoVertex};
  if (scene_->segment_valid(sparse_.position(c.vp), sparse_.position(c.vpp))) {
    connect(c.vp, c.vpp, admissions_.shortcut_edges);
    ++admissions_.shortcut_edge;
    record.direct_edge = true;
    shortcuts_.push_back(std::move(record));
    return;
  }
  // The dense route (search_ still holds q's search), extended at each end into the
  // neighbouring visibility regions: it starts at a dense vertex represented by v' and ends at
  // one represented by v''.
  std::vector<VertexId> route = search_.path_to(q, c.support);
  route.insert(route.begin(), interface_neighbor(q, c.vp));
  route.push_back(interface_neighbor(c.support, c.vpp));
  record.front_rep = rep_[route.front()];
  record.back_rep = rep_[route.back()];
  const std::vector<VertexId> kept = smooth(route);
  std::vector<VertexId> added;
  std::vector<VertexId> fresh;
  for (const VertexId d : kept) {
    if (sparse_of_dense_[d] != kNoVertex) {
      added.push_back(sparse_of_dense_[d]);
    } else {
      added.push_back(add_guard(d));
      fresh.push_back(added.back());
      ++admissions_.shortcut_path_vertices;
    }
  }
  for (std::size_t i = 1; i < added.size(); ++i) connect(added[i - 1], added[i], admissions_.shortcut_edges);
  // Each end joins the representative of its own dense support, checked like any edge.
  if (scene_->segment_valid(sparse_.position(added.front()), sparse_.position(c.vp))) {
    connect(added.front(), c.vp, admissions_.shortcut_edges);
  }
  if (scene_->segment_valid(sparse_.position(added.back()), sparse_.position(c.vpp))) {
    connect(added.back(), c.vpp, admissions_.shortcut_edges);
  }
  if (rules_.vertex_join) {
    for (const VertexId s : fresh) vertex_join(s, reachable_from(s));
  }
  ++admissions_.shortcut_path;
  record.path = std::move(added);
  shortcuts_.push_back(std::move(record));
}

std::vector<VertexId> SparsBuilder::smooth(const std::vector<VertexId>& path) const {
  // Greedy shortcutting: from each kept vertex jump to the farthest one in direct view.
  // Consecutive route vertices share a dense edge, so a one-step jump needs no check.
  std::vector<VertexId> kept{path.front()};
  std::size_t i = 0;
  while (i + 1 < path.size()) {
    std::size_t j = path.size() - 1;
    const Vec3& from = dense_.graph().position(path[i]);
    while (j > i + 1 && !scene_->segment_valid(from, dense_.graph().position(path[j]))) --j;
    kept.push_back(path[j]);
    i = j;
  }
  return kept;
}

VertexId SparsBuilder::interface_neighbor(VertexId dense_vertex, VertexId rep) const {
  VertexId best = kNoVertex;
  double best_cost = INFINITY;
  for (const Neighbor& n : dense_.graph().neighbors(dense_vertex)) {
    if (rep_[n.vertex] == rep && (n.cost < best_cost || (n.cost == best_cost && n.vertex < best))) {
      best = n.vertex;
      best_cost = n.cost;
    }
  }
  return best;  // exists: dense_vertex supports the interface with rep
}

std::size_t SparsBuilder::first_long_route(VertexId from, std::span<const VertexId> targets,
                                           std::span<const double> bounds) {
  // One goal-directed Dijkstra from `from` serves every target. A vertex v reached at distance
  // d is kept only if d + |v - target| is within some open target's bound: every prefix of a
  // route within its bound passes, so a target whose route is within its bound is settled at its
  // exact distance. A target is decided short when settled within its bound, long when settled
  // beyond it or once the search has passed its bound (what is settled later is farther). The
  // search stops as soon as the first long target in order is known, or every target is short.
  const double limit = *std::max_element(bounds.begin(), bounds.end());
  open_targets_.clear();  // (position, bound, index) of the targets not decided yet
  for (std::size_t k = 0; k < targets.size(); ++k)
    open_targets_.push_back({sparse_.position(targets[k]), bounds[k], k});
  target_state_.assign(targets.size(), TargetState::open);
  const auto useful = [&](VertexId v, double d) {
    const Vec3& p = sparse_.position(v);
    for (const OpenTarget& t : open_targets_) {
      const double slack = t.bound * (1.0 + 1e-12) - d;  // never prune a route at its bound by rounding
      if (slack >= 0.0 && (p - t.position).squaredNorm() <= slack * slack) return true;
    }
    return false;
  };
  sparse_search_.start(sparse_.vertex_count(), from);
  std::size_t first = 0;  // every target before it is short
  for (;;) {
    while (first < targets.size() && target_state_[first] == TargetState::short_route) ++first;
    if (first == targets.size() || target_state_[first] == TargetState::long_route) break;
    const auto [d, x] = sparse_search_.settle_next(sparse_, limit, useful);
    std::erase_if(open_targets_, [&](const OpenTarget& t) {
      if (x != kNoVertex && targets[t.index] == x) {
        target_state_[t.index] = d <= t.bound ? TargetState::short_route : TargetState::long_route;
        return true;
      }
      if (x == kNoVertex || t.bound < d) {  // nothing within its bound is left to settle
        target_state_[t.index] = TargetState::long_route;
        return true;
      }
      return false;
    });
  }
  // Every route this search found is a route: an upper bound on the pair's distance from now on.
  for (const VertexId v : sparse_search_.reached()) known_routes_.remember(from, v, sparse_search_.distance(v));
  return first;
}

void SparsBuilder::vertex_join(VertexId s, const std::vector<VertexId>& reachable) {
  // Nearest first: a near join may shorten the routes to the farther members.
  const Vec3 ps = sparse_.position(s);
  std::vector<VertexId> todo;
  std::vector<double> bounds;
  for (const VertexId w : reachable) {
    if (w == s) continue;
    const double bound = stretch_ * (sparse_.position(w) - ps).norm() + slack_now_;
    if (known_route(s, w) <= bound) continue;
    todo.push_back(w);
    bounds.push_back(bound);
  }
  std::size_t done = 0;
  while (done < todo.size()) {
    const std::span<const VertexId> rest(todo.data() + done, todo.size() - done);
    const std::size_t k = first_long_route(s, rest, std::span<const double>(bounds.data() + done, rest.size()));
    if (k == rest.size()) break;
    connect(s, rest[k], admissions_.join_edges);
    done += k + 1;  // the members before it have short routes, and keep them
  }
}

bool SparsBuilder::witnessed_pairs(VertexId through) {
  const Vec3 pq = current_.sample->q;
  const std::vector<VertexId> w = reachable_;  // W(q), nearest first
  if (w.size() < 2) return false;
  std::vector<double> to_q(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) to_q[i] = (sparse_.position(w[i]) - pq).norm();

  // The routes known between the members of W (upper bounds: still true after any repair below,
  // which updates the pairs it joins), looked up once: a pair joined within its bound directly
  // or through a third member needs no search.
  const std::size_t m = w.size();
  among_w_.assign(m * m, INFINITY);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = i + 1; j < m; ++j) among_w_[i * m + j] = among_w_[j * m + i] = known_route(w[i], w[j]);
  }
  const auto through_a_third = [&](std::size_t i, std::size_t j, double bound) {
    for (std::size_t x = 0; x < m; ++x) {
      if (x != i && x != j && among_w_[i * m + x] + among_w_[x * m + j] <= bound) return true;
    }
    return false;
  };

  VertexId admitted = kNoVertex;
  const std::size_t firsts = rules_.witness_nearest_only ? 1 : w.size() - 1;
  std::vector<VertexId> todo;
  std::vector<std::size_t> todo_index;  // of each todo entry in w
  std::vector<double> bounds;
  const auto joined = [&](std::size_t i, std::size_t j, double length) {
    among_w_[i * m + j] = among_w_[j * m + i] = std::min(among_w_[i * m + j], length);
  };
  for (std::size_t i = 0; i < firsts; ++i) {
    // A pair with a route already known within the bound (an edge, or a route an earlier
    // search found: routes only get shorter) needs no search.
    todo.clear();
    todo_index.clear();
    bounds.clear();
    for (std::size_t j = i + 1; j < w.size(); ++j) {
      if (w[i] < through && w[j] < through) continue;  // a pair the build witnessed already
      const double bound = stretch_ * (to_q[i] + to_q[j]) + slack_now_;
      if (among_w_[i * m + j] <= bound || through_a_third(i, j, bound)) continue;
      todo.push_back(w[j]);
      todo_index.push_back(j);
      bounds.push_back(bound);
    }
    std::size_t done = 0;
    while (done < todo.size()) {
      const std::span<const VertexId> rest(todo.data() + done, todo.size() - done);
      const std::size_t k = first_long_route(w[i], rest, std::span<const double>(bounds.data() + done, rest.size()));
      if (k == rest.size()) break;
      // Repair: the direct edge when its segment is valid, otherwise the route through q.
      const VertexId far = rest[k];
      const std::size_t j = todo_index[done + k];
      if (scene_->segment_valid(sparse_.position(w[i]), sparse_.position(far))) {
        connect(w[i], far, admissions_.witness_edges);
        ++admissions_.witness_edge;
        joined(i, j, (sparse_.position(w[i]) - sparse_.position(far)).norm());
      } else {
        if (admitted == kNoVertex) {
          admitted = admit();
          ++admissions_.witness_vertex;
        }
        connect(admitted, w[i], admissions_.witness_edges);
        connect(admitted, far, admissions_.witness_edges);
        joined(i, j, to_q[i] + to_q[j]);
      }
      done += k + 1;
    }
  }
  if (admitted != kNoVertex && rules_.vertex_join) vertex_join(admitted, w);
  return admitted != kNoVertex;
}

std::vector<VertexId> SparsBuilder::reachable_from(VertexId s) const {
  const Vec3 p = sparse_.position(s);
  std::vector<std::pair<double, std::uint32_t>> near;
  sparse_grid_.within(p, sparse_delta_, sparse_.positions(), near);
  std::vector<VertexId> out;
  for (const auto& [distance, v] : near) {
    if (v != s && scene_->segment_valid(p, sparse_.position(v))) out.push_back(v);
  }
  return out;
}

}  // namespace ispars::planning
