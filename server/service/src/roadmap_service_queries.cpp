// The roadmap service's long queries: verification, snapshots (SnapshotCache) and tours
// (checked and their targets resolved here, then admitted and run by the TourDesk).

#include <fmt/format.h>

#include <cmath>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "request_input.hpp"

namespace ispars::service {

std::uint64_t VerifyOutcome::violations() const { return planning::broken_promises(report, invariant_promised); }

VerifyOutcome RoadmapService::verify(const std::string& scene) const {
  const auto s = session(scene);
  if (stopping_) throw params::InputError("request", "scene", "the daemon is stopping");
  VerifyOutcome out;
  out.report = s->verify(kVerifyBudget);
  const auto recipe = s->status().recipe;
  out.invariant_promised = recipe && planning::promises_invariant(recipe->method);
  return out;
}

SnapshotSlice RoadmapService::snapshot(const std::string& scene, std::uint64_t version, std::uint64_t generation,
                                       std::uint32_t chunk_index, std::size_t poi_count) {
  const auto s = session(scene);
  return snapshots_.slice(*s, scene, version, generation, chunk_index, poi_count);
}

void RoadmapService::start_tour(const std::string& scene, TourRequest request, TourCallbacks callbacks) {
  const auto s = session(scene);
  if (!std::isfinite(request.budget_seconds) || !(request.budget_seconds > 0.0) ||
      request.budget_seconds > kMaxTourBudget) {
    throw params::InputError(kRequest, "budget",
                             fmt::format("must be in (0, {}] seconds, got {}", kMaxTourBudget, request.budget_seconds));
  }
  if (request.targets.size() > kMaxTourTargets) {
    throw params::InputError(kRequest, "targets",
                             fmt::format("{} given; at most {}", request.targets.size(), kMaxTourTargets));
  }
  if (!s->status().recipe || s->published().roadmap->vertex_count() == 0) {
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap yet", scene));
  }
  if (!request.task.empty()) {
    if (!request.targets.empty()) throw params::InputError(kRequest, "task", "give a task or targets, not both");
    // Coverage only grows (vertices and edges are only added): the later roadmap the tour runs
    // on sees them from the root's component too.
    const std::vector<InspectionTask> tasks = s->tasks();
    request.targets = task_targets(*s->published().roadmap, s->scene().pois().size(), tasks, request.task);
  } else if (request.targets.empty()) {
    // Every POI seen from the root's component, but removed tasks' (empty: every one).
    request.targets = live_targets(*s->published().roadmap, s->scene().pois().size(), s->tasks());
  }
  if (events_.on_tour) {
    callbacks.done = [done = std::move(callbacks.done), on_tour = events_.on_tour, scene](TourOutcome outcome) {
      on_tour(scene, outcome);
      if (done) done(std::move(outcome));
    };
  }
  tours_.admit(s, scene, std::move(request), std::move(callbacks));
}

}  // namespace ispars::service
