#include "ispars/spars_builder.hpp"

#include <algorithm>
#include <cmath>

namespace ispars {
namespace {

constexpr std::size_t kBatch = 256;

void insert_sorted(std::vector<VertexId>& list, VertexId x) {
  const auto it = std::lower_bound(list.begin(), list.end(), x);
  if (it == list.end() || *it != x) list.insert(it, x);
}

void erase_sorted(std::vector<VertexId>& list, VertexId x) {
  const auto it = std::lower_bound(list.begin(), list.end(), x);
  if (it != list.end() && *it == x) list.erase(it);
}

}  // namespace

SparsBuilder::SparsBuilder(const Scene& scene, const BuildOptions& options, bool inspection_test)
    : scene_(&scene),
      options_(options),
      inspection_test_(inspection_test),
      sparse_delta_(scene.config().sparse_delta),
      stretch_(scene.config().stretch),
      rng_(options.seed),
      dense_(scene, scene.config().dense_delta),
      sparse_(scene.pois().size()),
      sparse_grid_(scene.config().sparse_delta) {
  // Alg. 1, line 1: G_d and G_s start with the root.
  PreparedSample root;
  root.q = scene.config().root;
  root.valid = true;
  scene.visible_pois(root.q, root.visible);
  const VertexId r = dense_.insert(root.q, root.visible);
  sparse_of_dense_.push_back(kNoVertex);
  rep_.push_back(kNoVertex);
  rep_distance_.push_back(INFINITY);
  support_rep_.push_back(kNoVertex);
  partners_.emplace_back();
  add_guard(r);
}

void SparsBuilder::extend(std::size_t samples) {
  while (samples > 0) {
    const std::size_t n = std::min(samples, kBatch);
    prepare_samples(*scene_, rng_, n, options_.threads, batch_);
    for (const PreparedSample& sample : batch_) step(sample);
    samples -= n;
    samples_ += n;
  }
}

void SparsBuilder::step(const Vec3& sample) {
  PreparedSample prepared{sample, scene_->point_valid(sample), {}};
  if (prepared.valid) scene_->visible_pois(sample, prepared.visible);
  step(prepared);
}

void SparsBuilder::step(const PreparedSample& sample) {
  if (!sample.valid) return;
  // Lines 4-9: q joins G_d with its delta-edges.
  const VertexId q = dense_.insert(sample.q, sample.visible);
  sparse_of_dense_.push_back(kNoVertex);
  rep_.push_back(kNoVertex);
  rep_distance_.push_back(INFINITY);
  support_rep_.push_back(kNoVertex);
  partners_.emplace_back();

  // Line 10: W = ReachableGuards(q, Delta, G_s); its nearest member is rep(q).
  reachable_guards(sample.q);
  if (!reachable_.empty()) {
    rep_[q] = reachable_.front();
    rep_distance_[q] = (sparse_.position(reachable_.front()) - sample.q).norm();
  }
  // q's supports from its neighbours; each neighbour gains at most one partner, rep(q).
  update_supports(q);
  if (rep_[q] != kNoVertex) {
    for (const Neighbor& n : dense_.graph().neighbors(q)) add_partner(n.vertex, rep_[q]);
  }

  // Lines 11-17: guard, bridge, interface.
  if (reachable_.empty()) {
    add_guard(q);
    ++admissions_.guard;
  } else if (!bridge_test(q)) {
    interface_test(q);
  }
  // Lines 18-23 (Inspection-SPARS): admit q if it sees a POI no member of W sees.
  if (inspection_test_ && sparse_of_dense_[q] == kNoVertex && inspection_test(q)) {
    add_guard(q);
    ++admissions_.inspection;
  }
  // Lines 24-26: shortcut.
  if (sparse_of_dense_[q] == kNoVertex) shortcut_test(q);
}

void SparsBuilder::reachable_guards(const Vec3& q) {
  sparse_grid_.within(q, sparse_delta_, sparse_.positions(), nearby_);
  reachable_.clear();
  for (const auto& [distance, s] : nearby_) {
    if (scene_->segment_valid(sparse_.position(s), q)) reachable_.push_back(s);
  }
}

bool SparsBuilder::bridge_test(VertexId q) {
  // The nearest reachable member of each component of G_s that W touches.
  std::vector<VertexId> links;
  std::vector<VertexId> components;
  for (const VertexId w : reachable_) {
    const VertexId c = sparse_.component(w);
    if (std::find(components.begin(), components.end(), c) == components.end()) {
      components.push_back(c);
      links.push_back(w);
    }
  }
  if (links.size() < 2) return false;
  const VertexId s = add_guard(q);
  for (const VertexId w : links) sparse_.add_edge(s, w);
  ++admissions_.bridge;
  return true;
}

bool SparsBuilder::interface_test(VertexId q) {
  // The two nearest sparse vertices within Delta must both be reachable and not adjacent.
  if (nearby_.size() < 2 || reachable_.size() < 2) return false;
  const VertexId v0 = reachable_[0];
  const VertexId v1 = reachable_[1];
  if (nearby_[0].second != v0 || nearby_[1].second != v1) return false;
  if (sparse_.has_edge(v0, v1)) return false;
  if (scene_->segment_valid(sparse_.position(v0), sparse_.position(v1))) {
    sparse_.add_edge(v0, v1);
    ++admissions_.interface_edge;
  } else {
    const VertexId s = add_guard(q);
    sparse_.add_edge(s, v0);
    sparse_.add_edge(s, v1);
    ++admissions_.interface_vertex;
  }
  return true;
}

bool SparsBuilder::inspection_test(VertexId q) const {
  // I_Delta(q, G_s) = union of chi(w) over w in W; admit when chi(q) reaches outside it.
  const PoiBits seen = dense_.graph().visible(q);
  std::vector<std::uint64_t> cover(seen.size(), 0);
  for (const VertexId w : reachable_) unite(cover, sparse_.visible(w));
  return has_outside(seen, cover);
}

void SparsBuilder::shortcut_test(VertexId q) {
  const VertexId v = rep_[q];
  if (v == kNoVertex || partners_[q].empty()) return;

  // Candidate (v', v''): q supports the interface v|v'; v'' is a sparse neighbour of v, not v'
  // and not adjacent to v', with a known interface v|v''. The sparse route between the two
  // interfaces through v is estimated with midpoints: (|v - v'| + |v - v''|) / 2.
  struct Candidate {
    VertexId vp;
    VertexId vpp;
    double sparse_length;
    double dense_length = INFINITY;      // shortest dense route from q to a support of v|v''
    VertexId support = kNoVertex;        // that support
  };
  std::vector<Candidate> candidates;
  std::vector<VertexId> around_v;
  for (const Neighbor& n : sparse_.neighbors(v)) around_v.push_back(n.vertex);
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
  if (candidates.empty()) return;

  // One Dijkstra from q serves every candidate. A dense vertex x supports v|v'' when rep(x) = v
  // and v'' is among its partners; the first support settled is the nearest (ties: lowest id).
  // Only routes shorter than sparse_length / t can violate the stretch, so the search stops
  // once no pending candidate could still be violated, or none is pending.
  std::size_t pending = candidates.size();
  const auto pending_bound = [&] {
    double bound = 0.0;
    for (const Candidate& c : candidates) {
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
    for (Candidate& c : candidates) {
      if (c.support == kNoVertex && std::binary_search(partners_[x].begin(), partners_[x].end(), c.vpp)) {
        c.dense_length = d;
        c.support = x;
        --pending;
        resolved = true;
      }
    }
    if (resolved) bound = pending_bound();
  }

  for (const Candidate& c : candidates) {
    // This pair's sparse estimate against this pair's dense route (never another v''s).
    if (!(c.sparse_length > stretch_ * c.dense_length)) continue;

    ShortcutRecord record{v, c.vp, c.vpp, c.sparse_length, c.dense_length, false, {}, kNoVertex, kNoVertex};
    if (scene_->segment_valid(sparse_.position(c.vp), sparse_.position(c.vpp))) {
      sparse_.add_edge(c.vp, c.vpp);
      ++admissions_.shortcut_edge;
      record.direct_edge = true;
      shortcuts_.push_back(std::move(record));
      return;
    }
    // The dense route, extended at each end into the neighbouring visibility regions: it starts
    // at a dense vertex represented by v' and ends at one represented by v''.
    std::vector<VertexId> route = search_.path_to(q, c.support);
    route.insert(route.begin(), interface_neighbor(q, c.vp));
    route.push_back(interface_neighbor(c.support, c.vpp));
    record.front_rep = rep_[route.front()];
    record.back_rep = rep_[route.back()];
    const std::vector<VertexId> kept = smooth(route);
    std::vector<VertexId> added;
    for (const VertexId d : kept) {
      added.push_back(sparse_of_dense_[d] != kNoVertex ? sparse_of_dense_[d] : add_guard(d));
    }
    for (std::size_t i = 1; i < added.size(); ++i) sparse_.add_edge(added[i - 1], added[i]);
    // Each end joins the representative of its own dense support, checked like any edge.
    if (scene_->segment_valid(sparse_.position(added.front()), sparse_.position(c.vp))) {
      sparse_.add_edge(added.front(), c.vp);
    }
    if (scene_->segment_valid(sparse_.position(added.back()), sparse_.position(c.vpp))) {
      sparse_.add_edge(added.back(), c.vpp);
    }
    ++admissions_.shortcut_path;
    record.path = std::move(added);
    shortcuts_.push_back(std::move(record));
    return;
  }
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

VertexId SparsBuilder::add_guard(VertexId d) {
  const Vec3 p = dense_.graph().position(d);
  const VertexId s = sparse_.add_vertex(p, dense_.graph().visibility_table().ids(d));
  dense_of_sparse_.push_back(d);
  sparse_of_dense_[d] = s;
  sparse_grid_.insert(s, p);
  supports_.emplace_back();

  // Dense vertices within Delta that now see s closer than their representative take it.
  std::vector<std::pair<double, std::uint32_t>> near;
  dense_.within(p, sparse_delta_, near);
  std::vector<VertexId> changed;
  for (const auto& [distance, x] : near) {
    if (!(distance < rep_distance_[x])) continue;  // ties keep the older (lower id) vertex
    if (x != d && !scene_->segment_valid(p, dense_.graph().position(x))) continue;
    rep_[x] = s;
    rep_distance_[x] = distance;
    changed.push_back(x);
  }
  // Interface supports depend on the representatives of a vertex and of its neighbours.
  std::vector<VertexId> affected = changed;
  for (const VertexId x : changed) {
    for (const Neighbor& n : dense_.graph().neighbors(x)) affected.push_back(n.vertex);
  }
  std::sort(affected.begin(), affected.end());
  affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
  for (const VertexId x : affected) update_supports(x);
  return s;
}

void SparsBuilder::update_supports(VertexId x) {
  for (const VertexId vp : partners_[x]) erase_sorted(supports_[support_rep_[x]][vp], x);
  partners_[x].clear();
  support_rep_[x] = rep_[x];
  if (rep_[x] == kNoVertex) return;
  for (const Neighbor& n : dense_.graph().neighbors(x)) {
    const VertexId other = rep_[n.vertex];
    if (other != kNoVertex && other != rep_[x]) insert_sorted(partners_[x], other);
  }
  for (const VertexId vp : partners_[x]) insert_sorted(supports_[rep_[x]][vp], x);
}

void SparsBuilder::add_partner(VertexId x, VertexId partner) {
  const VertexId rep = rep_[x];
  if (rep == kNoVertex || rep == partner) return;
  auto& partners = partners_[x];
  const auto it = std::lower_bound(partners.begin(), partners.end(), partner);
  if (it != partners.end() && *it == partner) return;
  partners.insert(it, partner);
  insert_sorted(supports_[rep][partner], x);
}

std::vector<VertexId> SparsBuilder::interface_supports(VertexId v, VertexId v2) const {
  const auto it = supports_[v].find(v2);
  return it == supports_[v].end() ? std::vector<VertexId>{} : it->second;
}

}  // namespace ispars
