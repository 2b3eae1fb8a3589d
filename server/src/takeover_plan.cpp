#include "takeover_plan.hpp"

#include <fmt/format.h>

namespace ispars::server {
namespace {

TakeoverPlan keep(std::string outcome, bool refused = false) {
  TakeoverPlan plan;
  plan.refused = refused;
  plan.outcome = std::move(outcome);
  return plan;
}

std::string copy_words(const SessionStatus& mine) {
  return fmt::format("generation {}, {} samples", mine.recipe->generation, mine.samples_done);
}

}  // namespace

TakeoverPlan plan_takeover(const std::string& scene, const SessionStatus& mine, const std::string& my_fingerprint,
                           const FormerRoadmap& former) {
  if (!former.recipe) {
    if (former.generation > 0 && mine.recipe && mine.recipe->generation < former.generation) {
      TakeoverPlan plan = keep(fmt::format("scene '{}' taken over from {}, which dropped its roadmap (generation {}) "
                                           "after this daemon's copy ({}) was built: the copy is set aside",
                                           scene, former.owner, former.generation, copy_words(mine)));
      plan.set_aside = true;
      return plan;
    }
    return keep(fmt::format("scene '{}' taken over from {}, which held no roadmap of it", scene, former.owner));
  }
  if (!mine.recipe && mine.generation > former.recipe->generation) {
    return keep(fmt::format("scene '{}' taken over from {}: this daemon dropped the scene's roadmap (generation {}) "
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
  if (mine.recipe && same_roadmap(*mine.recipe, theirs)) {
    if (mine.samples_done >= former.samples) {
      return keep(fmt::format("scene '{}' taken over from {}: this daemon's copy ({}) holds the {} samples it had "
                              "reached or accepted",
                              scene, former.owner, copy_words(mine), former.samples));
    }
    TakeoverPlan plan;
    plan.action = TakeoverPlan::Action::extend;
    plan.extend_by = former.samples - mine.samples_done;
    plan.outcome = fmt::format("scene '{}' taken over from {}: continuing this daemon's copy ({}) to {} samples",
                               scene, former.owner, copy_words(mine), former.samples);
    return plan;
  }
  if (mine.recipe && mine.recipe->generation > theirs.generation) {
    return keep(fmt::format("scene '{}' taken over from {}: this daemon's copy ({}) is of a later build than its "
                            "generation {}, and is kept",
                            scene, former.owner, copy_words(mine), theirs.generation));
  }
  TakeoverPlan plan;
  plan.action = TakeoverPlan::Action::rebuild;
  plan.request = rebuild_request(theirs, former.samples);
  plan.set_aside = mine.recipe.has_value() || mine.state == SessionState::failed;
  plan.request.replace = plan.set_aside;
  plan.outcome = fmt::format("scene '{}' taken over from {}: rebuilding its {} roadmap (generation {}, seed {}) to {} "
                             "samples{}",
                             scene, former.owner, to_string(theirs.method), theirs.generation, theirs.seed,
                             former.samples,
                             mine.recipe ? fmt::format("; this daemon's older copy ({}) is set aside", copy_words(mine))
                                         : std::string());
  return plan;
}

}  // namespace ispars::server
