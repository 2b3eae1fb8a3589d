// Alg. 1, lines 24-26: Dobson & Bekris' shortcut test, through the dense graph.

#include <algorithm>
#include <cmath>

#include "ispars/builders/spars_builder.hpp"

namespace ispars {

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

}  // namespace ispars
