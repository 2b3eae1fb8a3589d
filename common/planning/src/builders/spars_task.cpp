// An inspection task added to a built roadmap: the new POIs' visibility from every vertex, then
// Alg. 1's inspection test run again for them over the build's samples, in order: the dense
// vertices with G_d, the seed's stream drawn again without (ispars2).

#include <algorithm>
#include <stdexcept>
#include <thread>
#include <vector>

#include "ispars/planning/builders/poi_visibility.hpp"
#include "ispars/planning/builders/spars_builder.hpp"

namespace ispars::planning {
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

// A sample of the build's stream drawn again, with the new POIs it sees (ids relative to the
// first new POI): none when it is invalid or sees none.
struct ReplayedSample {
  Vec3 q = Vec3::Zero();
  std::vector<PoiId> ids;
};

// Draws `count` samples from `stream` in order (three uniforms each, as prepare_samples does),
// then finds each one's new POIs on `threads` threads: the work that depends on the sample alone.
// The result does not depend on the thread count.
void replay_samples(const Scene& widened, scene_files::Rng& stream, std::size_t count, PoiId first, unsigned threads,
                    std::vector<ReplayedSample>& out) {
  out.resize(count);
  for (ReplayedSample& s : out) s.q = stream.uniform_in(widened.config().bounds);
  const VisibilityOracle& chi = widened.visibility();
  const auto find = [&](std::size_t from, std::size_t stride) {
    std::vector<PoiId> in_range;
    for (std::size_t i = from; i < count; i += stride) {
      ReplayedSample& s = out[i];
      s.ids.clear();
      chi.pois_in_range(s.q, in_range);  // ascending
      if (in_range.empty() || in_range.back() < first || !widened.point_valid(s.q)) continue;
      for (const PoiId id : in_range) {
        if (id >= first && chi.line_of_sight(s.q, id)) s.ids.push_back(id - first);
      }
    }
  };
  const std::size_t workers = std::clamp<std::size_t>(threads, 1, std::max<std::size_t>(1, count / 64));
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < workers; ++t) pool.emplace_back(find, t, workers);
  find(0, workers);
  for (std::thread& t : pool) t.join();
}

std::vector<PoiId> shifted(std::vector<PoiId> ids, PoiId by) {
  for (PoiId& id : ids) id += by;
  return ids;
}

// Every 256 steps, asks whether to go on; throws AdditionStopped when not.
void stop_if_asked(const std::function<bool()>& keep_going, std::size_t step) {
  if (step % 256 == 0 && keep_going && !keep_going()) {
    throw AdditionStopped("adding the task's POIs was stopped part way", true);
  }
}

bool any(PoiBits bits) {
  for (const std::uint64_t w : bits) {
    if (w != 0) return true;
  }
  return false;
}

}  // namespace

std::size_t SparsBuilder::add_pois(const Scene& widened, const std::function<bool()>& keep_going) {
  check_widened(*scene_, widened);
  const auto first = static_cast<PoiId>(scene_->pois().size());
  // The new POIs each vertex sees (ids from `first`): each dense vertex's with G_d, and each
  // sparse vertex's (its dense vertex's, or its own).
  PoiSetTable dense_fresh;
  PoiSetTable sparse_fresh(widened.pois().size() - first);
  if (rules_.dense_graph) {
    dense_fresh = new_poi_visibility(widened, dense_.graph(), first, keep_going, options_.threads);
    for (const VertexId x : dense_of_sparse_) sparse_fresh.append(dense_fresh.ids(x));
  } else {
    sparse_fresh = new_poi_visibility(widened, sparse_, first, keep_going, options_.threads);
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
  const auto first_guard = static_cast<VertexId>(sparse_.vertex_count());
  std::size_t added = rules_.dense_graph ? replay_dense(dense_fresh, sparse_fresh, keep_going)
                                         : replay_stream(sparse_fresh, first, keep_going);
  if (rules_.witnessed_pairs && added > 0) added += replay_witnesses(first_guard, keep_going);
  return added;
}

std::size_t SparsBuilder::replay_dense(const PoiSetTable& dense_fresh, PoiSetTable& sparse_fresh,
                                       const std::function<bool()>& keep_going) {
  std::size_t added = 0;
  for (VertexId x = 0; x < dense_fresh.rows(); ++x) {
    stop_if_asked(keep_going, x);
    if (sparse_of_dense_[x] != kNoVertex || !any(dense_fresh.row(x))) continue;
    const Vec3 q = dense_.graph().position(x);
    if (new_pois_covered(q, dense_fresh.row(x), sparse_fresh)) continue;
    reachable_guards(q);
    const VertexId s = add_guard(x);
    sparse_fresh.append(dense_fresh.ids(x));
    ++admissions_.inspection;
    ++added;
    join_task_guard(s);
  }
  return added;
}

std::size_t SparsBuilder::replay_stream(PoiSetTable& sparse_fresh, PoiId first,
                                        const std::function<bool()>& keep_going) {
  // The build's samples drawn again, in its order: its seed's stream (prepare_samples), in blocks
  // whose chi runs on the build's threads; the inspection test then takes them one by one.
  constexpr std::size_t kBlock = 1024;
  scene_files::Rng stream(options_.seed);
  std::vector<ReplayedSample> block;
  std::vector<std::uint64_t> seen(poi_words(sparse_fresh.poi_count()));
  std::size_t added = 0;
  for (std::size_t done = 0; done < samples_; done += kBlock) {
    stop_if_asked(keep_going, 0);
    replay_samples(*scene_, stream, std::min(kBlock, samples_ - done), first, options_.threads, block);
    for (const ReplayedSample& sample : block) {
      if (sample.ids.empty()) continue;
      std::fill(seen.begin(), seen.end(), 0);
      for (const PoiId id : sample.ids) seen[id / 64] |= std::uint64_t{1} << (id % 64);
      if (new_pois_covered(sample.q, seen, sparse_fresh)) continue;
      reachable_guards(sample.q);
      const VertexId s = sparse_.add_vertex(sample.q, scene_->visibility().visible_pois(sample.q));
      sparse_grid_.insert(s, sample.q);
      sparse_fresh.append(sample.ids);
      ++admissions_.inspection;
      ++added;
      join_task_guard(s);
    }
  }
  return added;
}

void SparsBuilder::join_task_guard(VertexId s) {
  if (rules_.vertex_join) {
    vertex_join(s, reachable_);
    return;
  }
  std::vector<VertexId> components;  // taken before any edge: an edge merges them
  std::vector<VertexId> links;
  for (const VertexId w : reachable_) {
    const VertexId c = sparse_.component(w);
    if (std::find(components.begin(), components.end(), c) != components.end()) continue;
    components.push_back(c);
    links.push_back(w);
  }
  for (const VertexId w : links) connect(s, w, admissions_.bridge_edges);
}

std::size_t SparsBuilder::replay_witnesses(VertexId first_guard, const std::function<bool()>& keep_going) {
  std::size_t admitted = 0;
  if (rules_.dense_graph) {
    const std::size_t dense_count = dense_.graph().vertex_count();
    for (VertexId x = 0; x < dense_count; ++x) {
      stop_if_asked(keep_going, x);
      if (sparse_of_dense_[x] != kNoVertex) continue;
      admitted += witness_again(dense_.graph().position(x), x, first_guard) ? 1 : 0;
    }
    return admitted;
  }
  scene_files::Rng stream(options_.seed);  // the build's samples drawn again, in its order (prepare_samples)
  for (std::size_t i = 0; i < samples_; ++i) {
    stop_if_asked(keep_going, i);
    admitted += witness_again(stream.uniform_in(scene_->config().bounds), kNoVertex, first_guard) ? 1 : 0;
  }
  return admitted;
}

bool SparsBuilder::witness_again(const Vec3& q, VertexId dense, VertexId first_guard) {
  // Cheap filters first: a new guard within Delta, and q not a sparse vertex itself (without G_d
  // an admitted sample is one); then the sample's validity and W(q) with its segments.
  sparse_grid_.within(q, sparse_delta_, sparse_.positions(), nearby_);
  bool near_guard = false;
  for (const auto& [distance, s] : nearby_) {
    if (distance == 0.0) return false;
    near_guard = near_guard || s >= first_guard;
  }
  if (!near_guard || (dense == kNoVertex && !scene_->point_valid(q))) return false;
  reachable_guards(q);
  if (std::none_of(reachable_.begin(), reachable_.end(), [&](VertexId w) { return w >= first_guard; })) return false;
  PreparedSample sample{q, true, {}};
  if (dense == kNoVertex) scene_->visible_pois(q, sample.visible);  // what admit() gives a vertex
  current_.sample = &sample;
  current_.dense = dense;
  current_.sparse = kNoVertex;
  const bool admitted = witnessed_pairs(first_guard);
  current_.sample = nullptr;
  return admitted;
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

}  // namespace ispars::planning
