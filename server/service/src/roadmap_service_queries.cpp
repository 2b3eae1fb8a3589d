// The roadmap service's long queries: snapshots in chunks (encoded once per version, kept for
// the chunks that follow), verification, and tours (admitted up to a bound, run on the tour
// workers, stopped by a cancel on their scene and by stop()).

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "ispars/builders/build_cost.hpp"
#include "ispars/builders/recipe_builder.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/tour/tour_closure.hpp"
#include "ispars/input_error.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "request_input.hpp"

namespace ispars {
namespace {

constexpr std::size_t kSnapshotsKept = 4;
// After the search, the tour's shortcut gets at most this long (a TOUR returns within its budget
// plus this, and a stop ends it at once); measured: 1 ms on a 100,000-sample Dense tour.
constexpr double kShortcutSeconds = 0.25;

// A snapshot's encoding at its worst: the batch copied out of the roadmap and its encoding, a
// compaction fold's work over the same vertices and edges (build_cost.hpp).
double snapshot_cost(const Roadmap& roadmap) {
  return static_cast<double>(roadmap.vertex_count()) * kFoldBytesPerVertex +
         static_cast<double>(roadmap.edge_count()) * kFoldBytesPerEdge;
}

// A tour at its worst: the search graph (the roadmap's size again) and a full distance matrix over
// its candidate viewpoints (at most TourClosureOptions::max_candidates; tour_closure.hpp).
double tour_cost(const Roadmap& roadmap) {
  const double candidates =
      static_cast<double>(std::min<std::size_t>(roadmap.vertex_count(), TourClosureOptions{}.max_candidates));
  return static_cast<double>(roadmap.vertex_count()) * kBytesPerVertex +
         static_cast<double>(roadmap.edge_count()) * kBytesPerEdge + candidates * candidates * sizeof(double);
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

SnapshotSlice RoadmapService::snapshot(const std::string& scene, std::uint64_t version, std::uint64_t generation,
                                       std::uint32_t chunk_index, std::size_t poi_count) {
  const auto s = session(scene);
  std::shared_ptr<const std::string> bytes;
  if (version != 0) {
    std::lock_guard lock(snapshots_mutex_);
    for (const auto& e : snapshots_) {
      if (e.scene == scene && e.generation == generation && e.version == version &&
          (poi_count == 0 || e.poi_count == poi_count)) {
        bytes = e.bytes;
        poi_count = e.poi_count;
      }
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
      throw InputError(kRequest, "snapshot_version",
                       fmt::format("version {} of roadmap generation {} is no longer available; start the snapshot again",
                                   version, generation));
    }
    // The encoding's worst case is leased before it is made, then only its size while it is kept.
    const auto lease = budget_->lease(snapshot_cost(*published.roadmap), fmt::format("a snapshot of scene '{}'", scene));
    auto encoded = std::make_unique<const std::string>(encode_batch(batch_range(*published.roadmap, 0, version)));
    lease->shrink_to(static_cast<double>(encoded->size()));
    bytes = std::shared_ptr<const std::string>(encoded.release(), [lease](const std::string* p) { delete p; });
    std::lock_guard lock(snapshots_mutex_);
    poi_count = published.roadmap->poi_count();
    snapshots_.push_back({scene, generation, version, poi_count, bytes});
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
  const bool queued = tours_.submit([this, s, request = std::move(request), callbacks = std::move(callbacks), stop, lease] {
    run_tour(s, request, callbacks, stop);
  });
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
  if (stop->load()) {  // cancelled while it waited for a worker: there is no tour to give
    if (callbacks.failed) {
      callbacks.failed(stopping_ ? "request: scene: the daemon stopped before the tour started"
                                 : "request: scene: the tour was cancelled before it started");
    }
    return;
  }
  try {
    const PublishedRoadmap published = session->published();
    const InspectionGraph graph = InspectionGraph::from_roadmap(*published.roadmap);
    GipOptions options;
    options.budget_seconds = request.budget_seconds;
    options.seed = request.seed;
    options.stop = stop.get();
    if (!request.targets.empty()) options.targets = request.targets;
    // Progress carries the best tour and the best bound so far; the two callbacks come from
    // different threads.
    std::mutex progress_mutex;
    double best_cost = 0.0, best_bound = 0.0;
    options.on_improvement = [&](double seconds, double cost) {
      std::lock_guard lock(progress_mutex);
      best_cost = cost;
      if (callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    options.on_bound = [&](double seconds, double bound) {
      std::lock_guard lock(progress_mutex);
      best_bound = bound;
      if (callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    TourOutcome outcome;
    outcome.result = solve_gip(graph, options);
    for (const VertexId v : outcome.result.tour.walk) outcome.waypoints.push_back(published.roadmap->position(v));
    const Scene& scene = session->scene();
    ShortcutOptions shortcut;
    shortcut.stop = stop.get();  // a stop leaves the path shortened in part, still valid
    shortcut.budget_seconds = kShortcutSeconds;
    const SegmentValid segment_valid = [&scene](const Vec3& a, const Vec3& b) { return scene.segment_valid(a, b); };
    outcome.shortcut = shortcut_tour(graph, published.roadmap->positions(), outcome.result.targets,
                                     outcome.result.tour, segment_valid, shortcut);
    outcome.shortcut_validation = check_shortcut_tour(graph, published.roadmap->positions(), options.root,
                                                      outcome.result.targets, outcome.shortcut, segment_valid);
    outcome.version = published.roadmap->version();
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
