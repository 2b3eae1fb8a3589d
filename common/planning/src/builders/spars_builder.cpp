#include "ispars/planning/builders/spars_builder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ispars/roadmap/build_recipe.hpp"

namespace ispars::planning {
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

SparsRules SparsRules::for_variant(SparsVariant variant, bool inspection_test) {
  SparsRules rules;
  rules.inspection_test = inspection_test;
  if (variant == SparsVariant::stretch) {
    rules.dense_shortcut = false;
    rules.vertex_join = true;
    rules.witnessed_pairs = true;
    rules.bridge_by_edge = true;
  }
  return rules;
}

SparsRules SparsRules::dense_free() {
  SparsRules rules = for_variant(SparsVariant::stretch, true);
  rules.dense_graph = false;
  return rules;
}

SparsBuilder::SparsBuilder(const Scene& scene, const BuildOptions& options, const SparsRules& rules)
    : scene_(&scene),
      options_(options),
      rules_(rules),
      sparse_delta_(scene.config().sparse_delta),
      stretch_(scene.config().stretch),
      stretch_slack_(options.stretch_slack * scene.config().sparse_delta),
      rng_(options.seed),
      dense_(scene, scene.config().dense_delta),
      sparse_(scene.pois().size()),
      sparse_grid_(scene.config().sparse_delta),
      known_routes_(options.known_route_pairs) {
  // A precondition of this library's callers, with the range the recipe declares.
  if (const std::string p = params::problem(kStretchSlack, options.stretch_slack); !p.empty()) {
    throw std::invalid_argument("stretch_slack " + p + " (a fraction of Delta)");
  }
  if (rules.dense_shortcut && !rules.dense_graph) {
    throw std::invalid_argument("the dense shortcut reads the dense graph: it cannot run without one");
  }
  // Alg. 1, line 1: G_d and G_s start with the root.
  PreparedSample root;
  root.q = scene.config().root;
  root.valid = true;
  scene.visible_pois(root.q, root.visible);
  if (!rules_.dense_graph) {
    const VertexId s = sparse_.add_vertex(root.q, root.visible);
    sparse_grid_.insert(s, root.q);
    return;
  }
  const VertexId r = dense_.insert(root.q, root.visible);
  sparse_of_dense_.push_back(kNoVertex);
  rep_.push_back(kNoVertex);
  rep_distance_.push_back(INFINITY);
  support_rep_.push_back(kNoVertex);
  partners_.emplace_back();
  add_guard(r);
}

SparsBuilder::SparsBuilder(const Scene& scene, const BuildOptions& options, const SparsRules& rules,
                           BuiltRoadmaps built)
    : SparsBuilder(scene, options, rules) {
  if (built.dense.has_value() != rules.dense_graph) {
    throw std::invalid_argument(rules.dense_graph ? "a builder with a dense graph resumes from its dense roadmap too"
                                                  : "a builder without a dense graph resumes from its roadmap alone");
  }
  sparse_ = std::move(built.roadmap);
  sparse_grid_ = PointGrid(sparse_delta_);
  for (VertexId s = 0; s < sparse_.vertex_count(); ++s) sparse_grid_.insert(s, sparse_.position(s));
  for (const RoadmapEdge& e : sparse_.edges()) known_routes_.remember(e.u, e.v, e.cost);
  if (rules_.dense_graph) {
    dense_ = DeltaPrm(scene, scene.config().dense_delta, std::move(*built.dense));
    dense_of_sparse_ = std::move(built.dense_ids);
    sparse_of_dense_.assign(dense_.graph().vertex_count(), kNoVertex);
    for (VertexId s = 0; s < dense_of_sparse_.size(); ++s) sparse_of_dense_[dense_of_sparse_[s]] = s;
    restore_representatives();
  }
  skip_samples(rng_, built.samples);
  samples_ = built.samples;
}

void SparsBuilder::restore_representatives() {
  const std::size_t n = dense_.graph().vertex_count();
  rep_.assign(n, kNoVertex);
  rep_distance_.assign(n, INFINITY);
  support_rep_.assign(n, kNoVertex);
  partners_.assign(n, {});
  supports_.assign(sparse_.vertex_count(), {});
  for (VertexId x = 0; x < n; ++x) {
    const Vec3& p = dense_.graph().position(x);
    // Nearest first, the lower id on a tie: the first in view is the one the build kept.
    sparse_grid_.within(p, sparse_delta_, sparse_.positions(), nearby_);
    for (const auto& [distance, s] : nearby_) {
      if (dense_of_sparse_[s] == x || scene_->segment_valid(sparse_.position(s), p)) {
        rep_[x] = s;
        rep_distance_[x] = distance;
        break;
      }
    }
  }
  for (VertexId x = 0; x < n; ++x) update_supports(x);
}

void SparsBuilder::extend(std::size_t samples) {
  while (samples > 0) {
    const std::size_t n = std::min(samples, kBatch);
    prepare_samples(*scene_, rng_, n, options_.threads, batch_);
    for (std::size_t k = 0; k < batch_.size(); ++k) {
      slack_now_ = slack_at(samples_ + k);
      step(batch_[k]);
    }
    samples -= n;
    samples_ += n;
  }
}

void SparsBuilder::step(const Vec3& sample) {
  PreparedSample prepared{sample, scene_->point_valid(sample), {}};
  if (prepared.valid) scene_->visible_pois(sample, prepared.visible);
  slack_now_ = slack_at(samples_);  // a given sample: the slack of now
  step(prepared);
}

void SparsBuilder::step(const PreparedSample& sample) {
  if (!sample.valid) return;
  current_.sample = &sample;
  current_.dense = kNoVertex;
  current_.sparse = kNoVertex;
  current_.seen.assign(poi_words(scene_->pois().size()), 0);
  for (const PoiId p : sample.visible) current_.seen[p / 64] |= std::uint64_t{1} << (p % 64);
  if (rules_.dense_graph) {
    // Lines 4-9: q joins G_d with its delta-edges.
    current_.dense = dense_.insert(sample.q, sample.visible);
    sparse_of_dense_.push_back(kNoVertex);
    rep_.push_back(kNoVertex);
    rep_distance_.push_back(INFINITY);
    support_rep_.push_back(kNoVertex);
    partners_.emplace_back();
  }

  // Line 10: W = ReachableGuards(q, Delta, G_s); its nearest member is rep(q).
  reachable_guards(sample.q);
  if (rules_.dense_graph) {
    const VertexId q = current_.dense;
    if (!reachable_.empty()) {
      rep_[q] = reachable_.front();
      rep_distance_[q] = (sparse_.position(reachable_.front()) - sample.q).norm();
    }
    // q's supports from its neighbours; each neighbour gains at most one partner, rep(q).
    update_supports(q);
    if (rep_[q] != kNoVertex) {
      for (const VertexId n : dense_.graph().neighbor_ids(q)) add_partner(n, rep_[q]);
    }
  }

  // Lines 11-17: guard, bridge, interface.
  if (reachable_.empty()) {
    admit();
    ++admissions_.guard;
  } else if (!bridge_test()) {
    interface_test();
  }
  // Lines 18-23 (Inspection-SPARS): admit q if it sees a POI no member of W sees.
  if (rules_.inspection_test && current_.sparse == kNoVertex && inspection_test()) {
    admit();
    ++admissions_.inspection;
  }
  // The sparse-vertex stretch rules: an admitted q joins the members of W it has no short route
  // to; a q left out witnesses the routes between the members of W.
  if (current_.sparse != kNoVertex) {
    if (rules_.vertex_join) vertex_join(current_.sparse, reachable_);
  } else if (rules_.witnessed_pairs) {
    witnessed_pairs();
  }
  // Lines 24-26: shortcut.
  if (rules_.dense_shortcut && current_.sparse == kNoVertex) shortcut_test(current_.dense);
}

VertexId SparsBuilder::admit() {
  if (current_.sparse != kNoVertex) return current_.sparse;
  if (rules_.dense_graph) {
    current_.sparse = add_guard(current_.dense);
  } else {
    current_.sparse = sparse_.add_vertex(current_.sample->q, current_.sample->visible);
    sparse_grid_.insert(current_.sparse, current_.sample->q);
  }
  return current_.sparse;
}

void SparsBuilder::reachable_guards(const Vec3& q) {
  sparse_grid_.within(q, sparse_delta_, sparse_.positions(), nearby_);
  reachable_.clear();
  for (const auto& [distance, s] : nearby_) {
    if (scene_->segment_valid(sparse_.position(s), q)) reachable_.push_back(s);
  }
}

bool SparsBuilder::bridge_test() {
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
  if (rules_.bridge_by_edge) {
    // Join the nearest member directly to each other component's member in view of it; q is
    // admitted only for the components it alone can join.
    std::vector<VertexId> through_q{links.front()};
    for (std::size_t i = 1; i < links.size(); ++i) {
      if (scene_->segment_valid(sparse_.position(links.front()), sparse_.position(links[i]))) {
        connect(links.front(), links[i], admissions_.bridge_edges);
        ++admissions_.bridge_edge;
      } else {
        through_q.push_back(links[i]);
      }
    }
    if (through_q.size() < 2) return true;
    links = std::move(through_q);
  }
  const VertexId s = admit();
  for (const VertexId w : links) connect(s, w, admissions_.bridge_edges);
  ++admissions_.bridge;
  return true;
}

bool SparsBuilder::interface_test() {
  // The two nearest sparse vertices within Delta must both be reachable and not adjacent.
  if (nearby_.size() < 2 || reachable_.size() < 2) return false;
  const VertexId v0 = reachable_[0];
  const VertexId v1 = reachable_[1];
  if (nearby_[0].second != v0 || nearby_[1].second != v1) return false;
  if (sparse_.has_edge(v0, v1)) return false;
  if (scene_->segment_valid(sparse_.position(v0), sparse_.position(v1))) {
    connect(v0, v1, admissions_.interface_edges);
    ++admissions_.interface_edge;
  } else {
    const VertexId s = admit();
    connect(s, v0, admissions_.interface_edges);
    connect(s, v1, admissions_.interface_edges);
    ++admissions_.interface_vertex;
  }
  return true;
}

bool SparsBuilder::inspection_test() const {
  // I_Delta(q, G_s) = union of chi(w) over w in W; admit when chi(q) reaches outside it.
  const PoiBits seen = current_.seen;
  std::vector<std::uint64_t> cover(seen.size(), 0);
  for (const VertexId w : reachable_) unite(cover, sparse_.visible(w));
  return has_outside(seen, cover);
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
    for (const VertexId n : dense_.graph().neighbor_ids(x)) affected.push_back(n);
  }
  std::sort(affected.begin(), affected.end());
  affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
  for (const VertexId x : affected) update_supports(x);
  return s;
}

void SparsBuilder::connect(VertexId u, VertexId v, std::uint64_t& cause) {
  if (!sparse_.add_edge(u, v)) return;
  ++cause;
  known_routes_.remember(u, v, (sparse_.position(u) - sparse_.position(v)).norm());  // no route is shorter
}

void SparsBuilder::update_supports(VertexId x) {
  for (const VertexId vp : partners_[x]) erase_sorted(supports_[support_rep_[x]][vp], x);
  partners_[x].clear();
  support_rep_[x] = rep_[x];
  if (rep_[x] == kNoVertex) return;
  for (const VertexId n : dense_.graph().neighbor_ids(x)) {
    const VertexId other = rep_[n];
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

}  // namespace ispars::planning
