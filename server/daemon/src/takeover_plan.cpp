#include "ispars/server/takeover_plan.hpp"

#include <fmt/format.h>

namespace ispars::server {
namespace {

TakeoverPlan keep(std::string outcome, bool refused = false) {
  TakeoverPlan plan;
  plan.refused = refused;
  plan.outcome = std::move(outcome);
  return plan;
}

std::string copy_words(const service::SessionStatus& mine) {
  return fmt::format("generation {}, {} samples", mine.recipe->generation, mine.samples_done);
}

// A continued copy with fewer task events than the former owner's, whose tasks did not arrive.
std::string missing_tasks(const service::SessionStatus& mine, const FormerRoadmap& former) {
  if (mine.task_events >= former.task_events) return "";
  return fmt::format(
      "; daemon {}'s roadmap had {} task events to this copy's {}, whose tasks did not reach this "
      "daemon: continued without them (they stay in its store)",
      former.owner, former.task_events, mine.task_events);
}

// What a rebuild does with the former owner's tasks, as the end of its sentence.
std::string task_words(const FormerRoadmap& former) {
  if (former.task_events == 0) return "";
  if (!former.tasks) {
    return fmt::format(
        "; its tasks ({} events) did not reach this daemon: rebuilt without them (they stay in daemon "
        "{}'s store, which outweighs this copy while it holds no more samples)",
        former.task_events, former.owner);
  }
  std::string names;
  for (const service::InspectionTask& t : *former.tasks) {
    if (t.removed) continue;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  return fmt::format(", with its {} task{} ({})", former.tasks->size(), former.tasks->size() == 1 ? "" : "s",
                     names.empty() ? std::string("all removed") : names);
}

// The plan when the former owner held no roadmap: nothing to continue, but a drop it made after
// this daemon's copy was built sets that copy aside.
TakeoverPlan plan_without_roadmap(const std::string& scene, const service::SessionStatus& mine,
                                  const FormerRoadmap& former) {
  if (former.generation > 0 && mine.recipe && mine.recipe->generation < former.generation) {
    TakeoverPlan plan =
        keep(fmt::format("scene '{}' taken over from {}, which dropped its roadmap (generation {}) "
                         "after this daemon's copy ({}) was built: the copy is set aside",
                         scene, former.owner, former.generation, copy_words(mine)));
    plan.set_aside = true;
    return plan;
  }
  return keep(fmt::format("scene '{}' taken over from {}, which held no roadmap of it", scene, former.owner));
}

}  // namespace

TakeoverPlan plan_takeover(const std::string& scene, const service::SessionStatus& mine,
                           const std::string& my_fingerprint, const FormerRoadmap& former) {
  if (!former.recipe) return plan_without_roadmap(scene, mine, former);
  if (!mine.recipe && mine.generation > former.recipe->generation) {
    return keep(
        fmt::format("scene '{}' taken over from {}: this daemon dropped the scene's roadmap (generation {}) "
                    "after daemon {}'s was built (generation {}): nothing is rebuilt, and its copy stays in "
                    "its store",
                    scene, former.owner, mine.generation, former.owner, former.recipe->generation));
  }
  if (former.samples == 0) {
    return keep(fmt::format("scene '{}' taken over from {}, which held no roadmap of it", scene, former.owner));
  }
  const RoadmapRecipe& theirs = *former.recipe;
  if (former.builder_version != 0 && former.builder_version != kBuilderVersion) {
    return keep(fmt::format("scene '{}': the roadmap of daemon {} was made by builder version {}, and this daemon "
                            "has version {}: it is not continued here (this daemon serves its own copy, if any)",
                            scene, former.owner, former.builder_version, kBuilderVersion),
                true);
  }
  if (!former.fingerprint.empty() && former.fingerprint != my_fingerprint) {
    return keep(fmt::format("scene '{}': this daemon's scene file differs from daemon {}'s (fingerprint {} there, {} "
                            "here): its roadmap is not continued here (this daemon serves its own copy, if any)",
                            scene, former.owner, former.fingerprint, my_fingerprint),
                true);
  }
  // The same roadmap, unless this copy lacks task events the former owner's had and this daemon
  // has those tasks (then it is rebuilt with them); without them it is continued as it is. The
  // same lineage only: an equal recipe built by another BUILD (another generation) is not it,
  // and the later build is what was acknowledged last.
  const bool lacks_tasks = mine.task_events < former.task_events && former.tasks.has_value();
  if (mine.recipe && same_roadmap(*mine.recipe, theirs) && mine.recipe->generation == theirs.generation &&
      !lacks_tasks) {
    if (mine.samples_done >= former.samples) {
      return keep(
          fmt::format("scene '{}' taken over from {}: this daemon's copy ({}) holds the {} samples it had "
                      "reached or accepted{}",
                      scene, former.owner, copy_words(mine), former.samples, missing_tasks(mine, former)));
    }
    TakeoverPlan plan;
    plan.action = TakeoverPlan::Action::extend;
    plan.extend_by = former.samples - mine.samples_done;
    plan.outcome = fmt::format("scene '{}' taken over from {}: continuing this daemon's copy ({}) to {} samples{}",
                               scene, former.owner, copy_words(mine), former.samples, missing_tasks(mine, former));
    return plan;
  }
  if (mine.recipe && mine.recipe->generation > theirs.generation) {  // (a later build: its tasks are its own)
    return keep(
        fmt::format("scene '{}' taken over from {}: this daemon's copy ({}) is of a later build than its "
                    "generation {}, and is kept",
                    scene, former.owner, copy_words(mine), theirs.generation));
  }
  TakeoverPlan plan;
  plan.action = TakeoverPlan::Action::rebuild;
  plan.request = service::rebuild_request(theirs, former.samples);
  plan.set_aside = mine.recipe.has_value() || mine.state == service::SessionState::failed;
  plan.request.replace = plan.set_aside;
  if (former.tasks) plan.tasks = *former.tasks;
  plan.outcome = fmt::format(
      "scene '{}' taken over from {}: rebuilding its {} roadmap (generation {}, seed {}) to {} samples{}{}", scene,
      former.owner, to_string(theirs.method), theirs.generation, theirs.seed, former.samples, task_words(former),
      !mine.recipe  ? std::string()
      : lacks_tasks ? fmt::format("; this daemon's copy ({}, {} task events of {}) is set aside", copy_words(mine),
                                  mine.task_events, former.task_events)
                    : fmt::format("; this daemon's older copy ({}) is set aside", copy_words(mine)));
  return plan;
}

}  // namespace ispars::server
