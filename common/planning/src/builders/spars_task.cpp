// An inspection task added to a built roadmap: the new POIs' visibility from every vertex, then
// Alg. 1's inspection test run again for them over the build's samples, in order: the dense
// vertices with G_d, the seed's stream drawn again without (ispars2).

#include <algorithm>
#include <stdexcept>

#include "ispars/builders/spars_builder.hpp"

namespace ispars {
namespace {

// Throws unless `widened` begins with `scene`'s POIs, in order.
void check_widened(const Scene& scene, const Scene& widened) {
  const auto& old_pois = scene.pois();
  const auto& new_pois = widened.pois();
  if (new_pois.size() < old_pois.size()) {
    throw std::invalid_argument("a task adds POIs: the new scene has fewer than this roadmap's");
  }
  for (std::size_t i = 0; i < old_pois.size(); ++i) {
    if (new_pois[i] != old_pois[i]) {
      throw std::invalid_argument("a task's scene must begin with this roadmap's POIs: POI " + std::to_string(i) +
                                  " differs");
    }
  }
}

// Each dense vertex's new POIs (ids relative to `first`): the candidates within sensor range,
// each with its own ray, as the widened scene's chi finds them.
PoiSetTable new_visibility(const Scene& widened, const Roadmap& dense, PoiId first) {
  PoiSetTable fresh(widened.pois().size() - first);
  std::vector<PoiId> in_range, ids;
  for (VertexId x = 0; x < dense.vertex_count(); ++x) {
    const Vec3& q = dense.position(x);
    widened.visibility().pois_in_range(q, in_range);
    ids.clear();
    for (const PoiId id : in_range) {
      if (id >= first && widened.visibility().line_of_sight(q, id)) ids.push_back(id - first);
    }
    fresh.append(ids);
  }
  return fresh;
}

std::vector<PoiId> shifted(std::vector<PoiId> ids, PoiId by) {
  for (PoiId& id : ids) id += by;
  return ids;
}

bool any(PoiBits bits) {
  for (const std::uint64_t w : bits) {
    if (w != 0) return true;
  }
  return false;
}

}  // namespace

std::size_t SparsBuilder::add_pois(const Scene& widened) {
  check_widened(*scene_, widened);
  const auto first = static_cast<PoiId>(scene_->pois().size());
  // The new POIs each vertex sees (ids from `first`): each dense vertex's with G_d, and each
  // sparse vertex's (its dense vertex's, or its own).
  PoiSetTable dense_fresh;
  PoiSetTable sparse_fresh(widened.pois().size() - first);
  if (rules_.dense_graph) {
    dense_fresh = new_visibility(widened, dense_.graph(), first);
    for (const VertexId x : dense_of_sparse_) sparse_fresh.append(dense_fresh.ids(x));
  } else {
    sparse_fresh = new_visibility(widened, sparse_, first);
  }
  // From here on the builder plans in the widened scene; every vertex sees what it sees there.
  scene_ = &widened;
  sparse_.widen_pois(widened.pois().size());
  for (VertexId s = 0; s < sparse_fresh.rows(); ++s) sparse_.add_visible(s, shifted(sparse_fresh.ids(s), first));
  if (rules_.dense_graph) {
    dense_.use_scene(widened);
    for (VertexId x = 0; x < dense_fresh.rows(); ++x) dense_.add_visible(x, shifted(dense_fresh.ids(x), first));
  }
  if (!rules_.inspection_test) return 0;
  slack_now_ = slack_at(samples_);
  return rules_.dense_graph ? replay_dense(dense_fresh, sparse_fresh) : replay_stream(sparse_fresh, first);
}

std::size_t SparsBuilder::replay_dense(const PoiSetTable& dense_fresh, PoiSetTable& sparse_fresh) {
  std::size_t added = 0;
  for (VertexId x = 0; x < dense_fresh.rows(); ++x) {
    if (sparse_of_dense_[x] != kNoVertex || !any(dense_fresh.row(x))) continue;
    const Vec3 q = dense_.graph().position(x);
    if (new_pois_covered(q, dense_fresh.row(x), sparse_fresh)) continue;
    reachable_guards(q);
    const VertexId s = add_guard(x);
    sparse_fresh.append(dense_fresh.ids(x));
    ++admissions_.inspection;
    ++added;
    if (rules_.vertex_join) vertex_join(s, reachable_);
  }
  return added;
}

std::size_t SparsBuilder::replay_stream(PoiSetTable& sparse_fresh, PoiId first) {
  // The build's samples drawn again, in its order: its seed's stream (prepare_samples).
  Rng stream(options_.seed);
  const VisibilityOracle& chi = scene_->visibility();
  std::vector<PoiId> in_range, ids;
  std::vector<std::uint64_t> seen(poi_words(sparse_fresh.poi_count()));
  std::size_t added = 0;
  for (std::size_t i = 0; i < samples_; ++i) {
    const Vec3 q = stream.uniform_in(scene_->config().bounds);
    chi.pois_in_range(q, in_range);
    if (in_range.empty() || in_range.back() < first || !scene_->point_valid(q)) continue;
    ids.clear();
    for (const PoiId id : in_range) {
      if (id >= first && chi.line_of_sight(q, id)) ids.push_back(id - first);
    }
    if (ids.empty()) continue;
    std::fill(seen.begin(), seen.end(), 0);
    for (const PoiId id : ids) seen[id / 64] |= std::uint64_t{1} << (id % 64);
    if (new_pois_covered(q, seen, sparse_fresh)) continue;
    reachable_guards(q);
    const VertexId s = sparse_.add_vertex(q, chi.visible_pois(q));
    sparse_grid_.insert(s, q);
    sparse_fresh.append(ids);
    ++admissions_.inspection;
    ++added;
    if (rules_.vertex_join) vertex_join(s, reachable_);
  }
  return added;
}

bool SparsBuilder::new_pois_covered(const Vec3& q, PoiBits seen, const PoiSetTable& fresh) {
  std::vector<std::uint64_t> cover(seen.size(), 0);
  sparse_grid_.within(q, sparse_delta_, sparse_.positions(), nearby_);
  for (const auto& [distance, s] : nearby_) {
    const PoiBits its = fresh.row(s);
    if (!has_outside(its, cover)) continue;  // adds nothing: no segment to check
    if (!scene_->segment_valid(sparse_.position(s), q)) continue;
    unite(cover, its);
    if (!has_outside(seen, cover)) return true;
  }
  return false;
}

}  // namespace ispars
