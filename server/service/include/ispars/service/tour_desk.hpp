#pragma once
// Tours: admitted up to a bound (tours per worker, queued or running), each leasing its worst case
// from the memory budget from admission to its end, run on the service's tour workers, and
// stopped by a cancel on their scene or by the service's stop (each then reports its best).

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ispars/planning/tour/flown_tour.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"
#include "ispars/service/memory_budget.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::service {

/// A tour request in typed form.
struct TourRequest {
  std::vector<PoiId> targets;   ///< Empty: every POI seen from the root's component.
  double budget_seconds = 1.0;  ///< In (0, kMaxTourBudget].
  std::uint64_t seed = 1;
  std::string task;  ///< Not empty: the targets are this task's POIs seen from the root's component.
};
inline constexpr double kMaxTourBudget = kTourBudget.max;
inline constexpr std::size_t kMaxTourTargets = 1'000'000;

/// A finished tour: the search's result on the roadmap version it searched, and that tour
/// shortcut by the scene's collision checker (tour_shortcut.hpp): the path a robot would fly.
struct TourOutcome {
  planning::GipResult result;                        ///< The roadmap search: its walk, trace and proven bound.
  std::vector<Vec3> waypoints;                       ///< The walk's positions.
  planning::ShortcutTour shortcut;                   ///< The walk shortcut (its stops are roadmap vertices).
  planning::ShortcutValidation shortcut_validation;  ///< check_shortcut_tour's independent check of it.
  /// The flown tour (flown_tour.hpp): stops, what each sees (from its independent check), length.
  std::vector<Vec3> flown_path;
  std::vector<std::vector<PoiId>> flown_sees;
  double flown_cost = 0.0;
  bool flown_valid = false;  ///< check_flown_tour passed.
  std::vector<planning::FlownStage> stages;
  std::size_t graph_vertices = 0;  ///< The graph the flown tour was last searched on.
  std::size_t graph_edges = 0;
  std::uint64_t version = 0;
};

/// How a tour reports: progress as it improves (best cost and proven bound so far, 0: none yet;
/// from two threads), then exactly one of done or failed, on a tour worker.
struct TourCallbacks {
  std::function<void(double seconds, double cost, double bound)> progress;
  std::function<void(TourOutcome outcome)> done;
  std::function<void(const std::string& error)> failed;
};

/// The service's tours, queued or running; safe from many threads.
class TourDesk {
 public:
  /// `workers` tours run at once, `per_worker` each are admitted; `stopping` is the service's stop.
  TourDesk(unsigned workers, std::size_t per_worker, std::shared_ptr<MemoryBudget> budget,
           const std::atomic<bool>& stopping);

  /// Admits a tour of `session`'s roadmap (scene `scene`; `request` checked, its targets
  /// resolved) and queues it. Throws InputError ("busy") past the bound or when the budget has
  /// no room for it, and when the workers are stopping.
  void admit(std::shared_ptr<RoadmapSession> session, const std::string& scene, TourRequest request,
             TourCallbacks callbacks);
  /// Stops the tours of `scene` (every scene when empty), queued or running; how many were not
  /// stopped before.
  std::size_t stop(const std::string& scene);
  /// Stops the workers: running tours (stopped first) report their best, queued ones are dropped.
  void close() { workers_.stop(); }

 private:
  using StopFlag = std::shared_ptr<std::atomic<bool>>;
  void run(const std::shared_ptr<RoadmapSession>& session, const TourRequest& request, const TourCallbacks& callbacks,
           const StopFlag& stop);
  void release(const StopFlag& stop);  // its admission and stop flag

  const std::size_t limit_;
  std::shared_ptr<MemoryBudget> budget_;
  const std::atomic<bool>& stopping_;
  std::mutex mutex_;
  std::size_t admitted_ = 0;
  std::multimap<std::string, StopFlag> running_;  // stop flags by scene
  WorkerPool workers_;
};

}  // namespace ispars::service
