#pragma once
// What a daemon does with a scene it takes over from another daemon (one that left, or handed
// the scene over): continue the former owner's roadmap from its own copy when it has one, keep a
// copy newer than the former owner's, and never replace a copy without setting it aside. Each
// decision carries the sentence the log and `ispars scenes list` show. Pure: the daemon carries
// the plan out (fleet_takeover.cpp).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/service/inspection_task.hpp"
#include "ispars/service/roadmap_session.hpp"

namespace ispars::server {

/// The former owner's roadmap, as its last status and announcement told the fleet.
struct FormerRoadmap {
  std::string owner;                    ///< Its server id.
  std::optional<RoadmapRecipe> recipe;  ///< Its recipe and generation; none when it held no roadmap.
  std::string fingerprint;              ///< Of the scene file it was built on (empty: unknown).
  std::uint32_t builder_version = 0;    ///< 0: unknown.
  std::uint64_t samples = 0;            ///< To reach here: what it committed and accepted.
  /// Its published roadmap's generation: with no recipe, that of the empty roadmap a DROP left
  /// (0: it never built or dropped the scene).
  std::uint64_t generation = 0;
  /// Its inspection tasks' events (added, plus removed), from its last status.
  std::uint64_t task_events = 0;
  /// Those tasks, in order, when all of them reached this daemon (ispars/tasks); none otherwise.
  std::optional<std::vector<service::InspectionTask>> tasks;
};

/// One takeover's decision.
struct TakeoverPlan {
  enum class Action {
    keep,     ///< Nothing to build: this daemon's copy serves as it is.
    extend,   ///< Extend this daemon's copy (the same roadmap) by `extend_by` samples.
    rebuild,  ///< Build `request` (the former owner's recipe and generation), setting any copy aside.
  };
  Action action = Action::keep;
  std::uint64_t extend_by = 0;
  BuildRequest request;
  /// With `rebuild`: the former owner's tasks, given to the scene before it is built (adopt_tasks).
  std::vector<service::InspectionTask> tasks;
  bool set_aside = false;  ///< This daemon's copy goes to DATA_DIR/.aside first (never deleted).
  bool refused = false;    ///< The former owner's roadmap cannot be continued here (named in `outcome`).
  std::string outcome;     ///< What was decided and why, in a sentence for the log and the scenes list.
};

/// The plan for taking `former`'s roadmap of `scene` over, given this daemon's session status
/// (`mine`, with its generation) and the fingerprint of its scene file. A drop counts as a copy
/// of its generation with no samples: a later drop on either side wins over an earlier build on
/// the other (the earlier copy here is set aside, never served again, never deleted).
[[nodiscard]] TakeoverPlan plan_takeover(const std::string& scene, const service::SessionStatus& mine,
                                         const std::string& my_fingerprint, const FormerRoadmap& former);

}  // namespace ispars::server
