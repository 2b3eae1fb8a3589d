#include "ispars/service/tour_desk.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/build_cost.hpp"
#include "ispars/planning/tour/tour_bound.hpp"
#include "ispars/planning/tour/tour_closure.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars::service {
namespace {

// The tour's corridor draws at most this many samples a round: it bounds the tour's memory
// (below) whatever the roadmap's build density asks for.
constexpr std::size_t kCorridorSamples = 4000;

// A tour at its worst (flown_tour.hpp): the roadmap's search graph, and a corridor's graph (the
// roadmap's again, the tube's samples and their joins) beside it; and the larger of the two
// searches' distance matrices over their candidate viewpoints (at most
// TourClosureOptions::max_candidates; tour_closure.hpp); and the LP bound at its size cap
// (tour_bound.hpp), unless the roadmap is past the LP's edge limit.
double tour_cost(const Roadmap& roadmap) {
  const planning::FlownTourOptions pipeline;
  const auto tube = static_cast<double>(kCorridorSamples);
  const auto vertices = static_cast<double>(roadmap.vertex_count());
  const auto edges = static_cast<double>(roadmap.edge_count());
  const double candidates =
      std::min(vertices + tube, static_cast<double>(planning::TourClosureOptions{}.max_candidates));
  const planning::TourBoundOptions lp;
  const double lp_bytes = roadmap.edge_count() > lp.max_edges
                              ? 0.0
                              : static_cast<double>(lp.max_cut_nonzeros) * planning::kLpBytesPerNonzero;
  return lp_bytes + (2.0 * vertices + tube) * planning::kBytesPerVertex +
         (2.0 * edges + tube * static_cast<double>(pipeline.corridor_max_joins)) * planning::kBytesPerEdge +
         candidates * candidates * sizeof(double);
}

// A finished pipeline as the service reports it, with the walk's shortcut checked on its own.
TourOutcome tour_outcome(planning::FlownTour flown, const InspectionGraph& graph, const Roadmap& roadmap,
                         const planning::Scene& scene) {
  TourOutcome o;
  for (const VertexId v : flown.search.tour.walk) o.waypoints.push_back(roadmap.position(v));
  const planning::SegmentValid segment_valid = [&scene](const Vec3& a, const Vec3& b) {
    return scene.segment_valid(a, b);
  };
  o.shortcut_validation = planning::check_shortcut_tour(graph, roadmap.positions(), 0, flown.search.targets,
                                                        flown.roadmap_shortcut, segment_valid);
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

TourDesk::TourDesk(unsigned workers, std::size_t per_worker, std::shared_ptr<MemoryBudget> budget,
                   const std::atomic<bool>& stopping)
    : limit_(per_worker * std::max(1u, workers)),
      budget_(std::move(budget)),
      stopping_(stopping),
      workers_(std::max(1u, workers)) {}

void TourDesk::admit(std::shared_ptr<RoadmapSession> session, const std::string& scene, TourRequest request,
                     TourCallbacks callbacks) {
  // Its worst case is leased from admission to its end (queued or running).
  const auto lease =
      budget_->lease(tour_cost(*session->published().roadmap), fmt::format("a tour of scene '{}'", scene));
  // At most per_worker per worker wait or run; past that the request is refused, not queued.
  auto stop = std::make_shared<std::atomic<bool>>(false);
  {
    std::lock_guard lock(mutex_);
    if (admitted_ >= limit_) {
      throw params::InputError(
          kRequest, "kind",
          fmt::format("busy: {} tours are queued or running (this daemon's limit); retry later", limit_));
    }
    ++admitted_;
    running_.emplace(scene, stop);  // a cancel on the scene stops it, queued or running
  }
  const bool queued =
      workers_.submit([this, session = std::move(session), request = std::move(request),
                       callbacks = std::move(callbacks), stop, lease] { run(session, request, callbacks, stop); });
  if (!queued) {  // only when stopping
    release(stop);
    throw params::InputError(kRequest, "scene", "the daemon is stopping");
  }
}

void TourDesk::release(const StopFlag& stop) {
  std::lock_guard lock(mutex_);
  --admitted_;
  for (auto it = running_.begin(); it != running_.end(); ++it) {
    if (it->second == stop) {
      running_.erase(it);
      return;
    }
  }
}

std::size_t TourDesk::stop(const std::string& scene) {
  std::lock_guard lock(mutex_);
  std::size_t stopped = 0;
  for (auto& [name, flag] : running_) {
    if (!scene.empty() && name != scene) continue;
    if (!flag->exchange(true)) ++stopped;
  }
  return stopped;
}

void TourDesk::run(const std::shared_ptr<RoadmapSession>& session, const TourRequest& request,
                   const TourCallbacks& callbacks, const StopFlag& stop) {
  struct Release {
    TourDesk& desk;
    const StopFlag& stop;
    ~Release() { desk.release(stop); }
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
    planning::FlownTourOptions options;  // the pipeline's defaults: one tour model with the lab and Python
    options.search.budget_seconds = request.budget_seconds;
    options.search.seed = request.seed;
    options.search.stop = stop.get();
    if (!request.targets.empty()) options.search.targets = request.targets;
    options.build_samples = session->status().samples_done;
    options.corridor_max_samples = kCorridorSamples;
    // Progress carries the best tour and the best bound so far (0: none yet); the two callbacks
    // come from different threads. None is sent before the first tour exists, so every progress
    // names a real tour's cost; a bound proven before it rides on the first one.
    std::mutex progress_mutex;
    bool have_tour = false;
    double best_cost = 0.0, best_bound = 0.0;
    options.search.on_improvement = [&](double seconds, double cost) {
      std::lock_guard lock(progress_mutex);
      have_tour = true;
      best_cost = cost;
      if (callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    options.search.on_bound = [&](double seconds, double bound) {
      std::lock_guard lock(progress_mutex);
      best_bound = bound;
      if (have_tour && callbacks.progress) callbacks.progress(seconds, best_cost, best_bound);
    };
    // The scene as the roadmap was built in (its recipe's deltas, its tasks' POIs), taken after
    // the roadmap: never older than it.
    const std::shared_ptr<const planning::Scene> with_tasks = session->scene_with_tasks();
    const std::optional<RoadmapRecipe> recipe = session->status().recipe;
    const planning::Scene scene = recipe ? session_detail::scene_for(*with_tasks, *recipe) : *with_tasks;
    TourOutcome outcome = tour_outcome(planning::fly_tour(scene, graph, published.roadmap->positions(), options), graph,
                                       *published.roadmap, scene);
    if (callbacks.done) callbacks.done(std::move(outcome));
  } catch (const params::InputError& e) {
    if (callbacks.failed) callbacks.failed(e.what());
  } catch (const std::exception& e) {
    if (stop->load()) {  // stopped before the search found a first tour
      if (callbacks.failed) callbacks.failed(std::string("request: scene: the tour was stopped: ") + e.what());
      return;
    }
    if (callbacks.failed) callbacks.failed(std::string("internal error: ") + e.what());
  }
}

}  // namespace ispars::service
