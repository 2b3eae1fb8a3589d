// The roadmap service's long queries: snapshots in chunks (encoded once per version, kept for
// the chunks that follow), verification, and tours (admitted up to a bound, run on the tour
// workers, stopped by a cancel on their scene and by stop()).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "ispars/builders/build_cost.hpp"
#include "ispars/builders/recipe_builder.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "ispars/tour/tour_bound.hpp"
#include "ispars/tour/tour_closure.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars {
namespace {

constexpr std::size_t kSnapshotsKept = 4;
// A kept encoding unused this long is dropped (its lease given back) at the next snapshot; any
// is dropped at once when a build, tour or snapshot needs its memory (the budget's reclaimer).
constexpr std::chrono::seconds kSnapshotKeptFor{60};
// A snapshot's encoding at its worst: the batch copied out of the roadmap and its encoding, a
// compaction fold's work over the same vertices and edges (build_cost.hpp).
double snapshot_cost(const Roadmap& roadmap) {
  return static_cast<double>(roadmap.vertex_count()) * kFoldBytesPerVertex +
         static_cast<double>(roadmap.edge_count()) * kFoldBytesPerEdge;
}

// The tour's corridor draws at most this many samples a round: it bounds the tour's memory
// (below) whatever the roadmap's build density asks for.
constexpr std::size_t kCorridorSamples = 4000;

// A tour at its worst (flown_tour.hpp): the roadmap's search graph, and a corridor's graph (the
// roadmap's again, the tube's samples and their joins) beside it; and the larger of the two
// searches' distance matrices over their candidate viewpoints (at most
// TourClosureOptions::max_candidates; tour_closure.hpp); and the LP bound at its size cap
// (tour_bound.hpp), unless the roadmap is past the LP's edge limit.
double tour_cost(const Roadmap& roadmap) {
  const FlownTourOptions pipeline;
  const auto tube = static_cast<double>(kCorridorSamples);
  const auto vertices = static_cast<double>(roadmap.vertex_count());
  const auto edges = static_cast<double>(roadmap.edge_count());
  const double candidates = std::min(vertices + tube, static_cast<double>(TourClosureOptions{}.max_candidates));
  const TourBoundOptions lp;
  const double lp_bytes =
      roadmap.edge_count() > lp.max_edges ? 0.0 : static_cast<double>(lp.max_cut_nonzeros) * kLpBytesPerNonzero;
  return lp_bytes + (2.0 * vertices + tube) * kBytesPerVertex +
         (2.0 * edges + tube * static_cast<double>(pipeline.corridor_max_joins)) * kBytesPerEdge +
         candidates * candidates * sizeof(double);
}

// A finished pipeline as the service reports it, with the walk's shortcut checked on its own.
TourOutcome tour_outcome(FlownTour flown, const InspectionGraph& graph, const Roadmap& roadmap, const Scene& scene) {
  TourOutcome o;
  for (const VertexId v : flown.search.tour.walk) o.waypoints.push_back(roadmap.position(v));
  const SegmentValid segment_valid = [&scene](const Vec3& a, const Vec3& b) { return scene.segment_valid(a, b); };
  o.shortcut_validation =
      check_shortcut_tour(graph, roadmap.positions(), 0, flown.search.targets, flown.roadmap_shortcut, segment_valid);
  o.flown_path = std::move(flown.stops);
  o.flown_sees = std::move(flown.check.sees);
  o.flown_cost = flown.cost;
  o.flown_valid = flown.check.valid();
  o.stages = std::move(flown.stages);
  o.graph_vertices = flown.graph_vertices;
  o.graph_edges = flown.graph_edges;
  o.shortcut = std::move(flown.roadmap_shortcut);
  o.result = std::move(flown.search);
  o.version = roadmap.version();
  return o;
}

}  // namespace

std::uint64_t VerifyOutcome::violations() const { return broken_promises(report, invariant_promised); }

VerifyOutcome RoadmapService::verify(const std::string& scene) const {
  const auto s = session(scene);
  if (stopping_) throw InputError("request", "scene", "the daemon is stopping");
  VerifyOutcome out;
  out.report = s->verify(kVerifyBudget);
  const auto recipe = s->status().recipe;
  out.invariant_promised = recipe && promises_invariant(recipe->method);
  return out;
}

void RoadmapService::drop_kept_snapshots() {
  std::vector<EncodedSnapshot> dropped;
  {
    std::lock_guard lock(snapshots_mutex_);
    dropped.swap(snapshots_);
  }
  if (!dropped.empty()) spdlog::info("dropped {} kept snapshot encodings: their memory is needed", dropped.size());
}

SnapshotSlice RoadmapService::snapshot(const std::string& scene, std::uint64_t version, std::uint64_t generation,
                                       std::uint32_t chunk_index, std::size_t poi_count) {
  const auto s = session(scene);
  std::shared_ptr<const std::string> bytes;
  std::vector<EncodedSnapshot> expired;  // released outside the lock
  {
    std::lock_guard lock(snapshots_mutex_);
    const auto now = std::chrono::steady_clock::now();
    for (auto it = snapshots_.begin(); it != snapshots_.end();) {
      if (now - it->used > kSnapshotKeptFor) {
        expired.push_back(std::move(*it));
        it = snapshots_.erase(it);
        continue;
      }
      if (version != 0 && it->scene == scene && it->generation == generation && it->version == version &&
          (poi_count == 0 || it->poi_count == poi_count)) {
        bytes = it->bytes;
        poi_count = it->poi_count;
        it->used = now;
      }
      ++it;
    }
  }
  if (!bytes) {
    const PublishedRoadmap published = s->published();
    if (version == 0) {
      generation = published.generation;
      version = published.roadmap->version();
      poi_count = published.roadmap->poi_count();
    } else if (published.generation != generation || published.roadmap->version() < version ||
               (poi_count != 0 && published.roadmap->poi_count() != poi_count)) {
      throw InputError(
          kRequest, "snapshot_version",
          fmt::format("version {} of roadmap generation {} is no longer available; start the snapshot again", version,
                      generation));
    }
    // The encoding's worst case is leased before it is made, then only its size while it is kept.
    const auto lease =
        budget_->lease(snapshot_cost(*published.roadmap), fmt::format("a snapshot of scene '{}'", scene));
    // Stoppable between slices: a daemon that stops does not wait out a large roadmap's encoding.
    std::optional<std::string> made =
        encode_prefix(*published.roadmap, version, [this] { return !readers_stopped_.load(); });
    if (!made) {
      throw InputError(kRequest, "scene",
                       fmt::format("the snapshot of scene '{}' was stopped: the daemon is stopping", scene));
    }
    auto encoded = std::make_unique<const std::string>(std::move(*made));
    lease->shrink_to(static_cast<double>(encoded->size()));
    bytes = std::shared_ptr<const std::string>(encoded.release(), [lease](const std::string* p) { delete p; });
    std::lock_guard lock(snapshots_mutex_);
    poi_count = published.roadmap->poi_count();
    snapshots_.push_back({scene, generation, version, poi_count, bytes, std::chrono::steady_clock::now()});
    if (snapshots_.size() > kSnapshotsKept) snapshots_.erase(snapshots_.begin());
  }
  const std::size_t count = std::max<std::size_t>(1, (bytes->size() + kSnapshotChunkBytes - 1) / kSnapshotChunkBytes);
  if (chunk_index >= count) {
    throw InputError(kRequest, "chunk_index", fmt::format("{} is past the last chunk ({})", chunk_index, count - 1));
  }
  SnapshotSlice slice;
  slice.generation = generation;
  slice.version = version;
  slice.chunk_index = chunk_index;
  slice.chunk_count = static_cast<std::uint32_t>(count);
  slice.poi_count = poi_count;
  slice.begin = std::size_t{chunk_index} * kSnapshotChunkBytes;
  slice.end = std::min(bytes->size(), slice.begin + kSnapshotChunkBytes);
  slice.encoded = std::move(bytes);
  return slice;
}

void RoadmapService::start_tour(const std::string& scene, TourRequest request, TourCallbacks callbacks) {
  const auto s = session(scene);
  if (!std::isfinite(request.budget_seconds) || !(request.budget_seconds > 0.0) ||
      request.budget_seconds > kMaxTourBudget) {
    throw InputError(kRequest, "budget",
                     fmt::format("must be in (0, {}] seconds, got {}", kMaxTourBudget, request.budget_seconds));
  }
  if (request.targets.size() > kMaxTourTargets) {
    throw InputError(kRequest, "targets", fmt::format("{} given; at most {}", request.targets.size(), kMaxTourTargets));
  }
  if (!s->status().recipe || s->published().roadmap->vertex_count() == 0) {
    throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap yet", scene));
  }
  if (!request.task.empty()) {
    if (!request.targets.empty()) throw InputError(kRequest, "task", "give a task or targets, not both");
    // Coverage only grows (vertices and edges are only added): the later roadmap the tour runs
    // on sees them from the root's component too.
    const std::vector<InspectionTask> tasks = s->tasks();
    request.targets = task_targets(*s->published().roadmap, s->scene().pois().size(), tasks, request.task);
  } else if (request.targets.empty()) {
    // Every POI seen from the root's component, but removed tasks' (empty: every one).
    request.targets = live_targets(*s->published().roadmap, s->scene().pois().size(), s->tasks());
  }
  // Its worst case is leased from admission to its end (queued or running).
  const auto lease = budget_->lease(tour_cost(*s->published().roadmap), fmt::format("a tour of scene '{}'", scene));
  // At most tours_per_worker per worker wait or run; past that the request is refused, not queued.
  const std::size_t limit = settings_.tours_per_worker * std::max(1u, settings_.tour_workers);
  auto stop = std::make_shared<std::atomic<bool>>(false);
  {
    std::lock_guard lock(tours_mutex_);
    if (tours_admitted_ >= limit) {
      throw InputError(kRequest, "kind",
                       fmt::format("busy: {} tours are queued or running (this daemon's limit); retry later", limit));
    }
    ++tours_admitted_;
    running_tours_.emplace(scene, stop);  // a cancel on the scene stops it, queued or running
  }
  const bool queued = tours_.submit([this, s, request = std::move(request), callbacks = std::move(callbacks), stop,
                                     lease] { run_tour(s, request, callbacks, stop); });
  if (!queued) {  // only when stopping
    release_tour(stop);
    throw InputError(kRequest, "scene", "the daemon is stopping");
  }
}

void RoadmapService::release_tour(const std::shared_ptr<std::atomic<bool>>& stop) {
  std::lock_guard lock(tours_mutex_);
  --tours_admitted_;
  for (auto it = running_tours_.begin(); it != running_tours_.end(); ++it) {
    if (it->second == stop) {
      running_tours_.erase(it);
      return;
    }
  }
}

void RoadmapService::run_tour(const std::shared_ptr<RoadmapSession>& session, const TourRequest& request,
                              const TourCallbacks& callbacks, const std::shared_ptr<std::atomic<bool>>& stop) {
  struct Release {
    RoadmapService& service;
    const std::shared_ptr<std::atomic<bool>>& stop;
    ~Release() { service.release_tour(stop); }
  } release{*this, stop};
  if (stopping_) stop->store(true);  // stop() began before the tour started
  if (stop->load()) {                // cancelled while it waited for a worker: there is no tour to give
    if (callbacks.failed) {
      callbacks.failed(stopping_ ? "request: scene: the daemon stopped before the tour started"
                                 : "request: scene: the tour was cancelled before it started");
    }
    return;
  }
  try {
    const PublishedRoadmap published = session->published();
    const InspectionGraph graph = InspectionGraph::from_roadmap(*published.roadmap);
    FlownTourOptions options;  // the pipeline's defaults: one tour model with the lab and Python
    options.search.budget_seconds = request.budget_seconds;
    options.search.seed = request.seed;
    options.search.stop = stop.get();
    if (!request.targets.empty()) options.search.targets = request.targets;
    options.build_samples = session->status().samples_done;
    options.corridor_max_samples = kCorridorSamples;
    // Progress carries the best tour and the best bound so far; the two callbacks come from
    // different threads.
    std::mutex progress_mutex;
    double best_cost = 0.0, best_bound = 0.0;
    options.search.on_improvement = [&](double seconds, double cost) {
      std::lock_guard lock(progress_mutex);
      best_cost = cost;
      if (callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    options.search.on_bound = [&](double seconds, double bound) {
      std::lock_guard lock(progress_mutex);
      best_bound = bound;
      if (callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    // The scene as the roadmap was built in (its recipe's deltas, its tasks' POIs), taken after
    // the roadmap: never older than it.
    const std::shared_ptr<const Scene> with_tasks = session->scene_with_tasks();
    const std::optional<RoadmapRecipe> recipe = session->status().recipe;
    const Scene scene = recipe ? session_detail::scene_for(*with_tasks, *recipe) : *with_tasks;
    TourOutcome outcome =
        tour_outcome(fly_tour(scene, graph, published.roadmap->positions(), options), graph, *published.roadmap, scene);
    if (callbacks.done) callbacks.done(std::move(outcome));
  } catch (const InputError& e) {
    if (callbacks.failed) callbacks.failed(e.what());
  } catch (const std::exception& e) {
    if (stop->load()) {  // stopped before the search found a first tour
      if (callbacks.failed) callbacks.failed(std::string("request: scene: the tour was stopped: ") + e.what());
      return;
    }
    if (callbacks.failed) callbacks.failed(std::string("internal error: ") + e.what());
  }
}

}  // namespace ispars
