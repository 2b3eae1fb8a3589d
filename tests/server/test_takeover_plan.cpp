// plan_takeover: what a daemon does with a scene it takes over. Its own copy of the same roadmap
// is continued, never replaced; a newer copy is kept; an older one is set aside, never deleted;
// a roadmap of another scene file or builder version is not continued, by name.

#include <gtest/gtest.h>

#include "ispars/server/takeover_plan.hpp"

namespace ispars::server {
namespace {

RoadmapRecipe recipe(std::uint64_t generation, std::uint64_t seed = 1) {
  RoadmapRecipe r;
  r.scene += 's';  // appended: GCC 12 warns falsely on assigning a short literal here
  r.method = BuildMethod::ispars;
  r.seed = seed;
  r.generation = generation;
  r.scene_fingerprint += 'f';
  r.builder_version = kBuilderVersion;
  return r;
}

service::SessionStatus mine(std::optional<RoadmapRecipe> r, std::uint64_t samples) {
  service::SessionStatus s;
  s.scene += 's';
  s.state = r ? service::SessionState::idle : service::SessionState::empty;
  s.recipe = std::move(r);
  s.samples_done = s.samples_target = samples;
  return s;
}

FormerRoadmap former(std::optional<RoadmapRecipe> r, std::uint64_t samples) {
  FormerRoadmap f;
  f.owner += 'o';
  f.recipe = std::move(r);
  f.fingerprint += 'f';
  f.builder_version = kBuilderVersion;
  f.samples = samples;
  return f;
}

// The a/b sequence at its last step: this daemon holds 20,000 samples of the roadmap
// whose former owner had 10,000. Nothing is built, and above all nothing is replaced.
TEST(TakeoverPlan, AnOwnCopyHoldingAtLeastWhatWasAskedIsKept) {
  const TakeoverPlan plan = plan_takeover("s", mine(recipe(7), 20000), "f", former(recipe(7), 10000));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::keep);
  EXPECT_FALSE(plan.set_aside);
  EXPECT_FALSE(plan.refused);
  EXPECT_NE(plan.outcome.find("holds the 10000 samples"), std::string::npos) << plan.outcome;
  // An equal recipe under an older generation (another BUILD) is not the same lineage: the
  // later build was acknowledged last, and is rebuilt (this copy set aside). Under a newer
  // generation this copy is the later build, and is kept. (The history campaign found a daemon
  // serving its older generation for a later acknowledged build of an equal recipe.)
  const TakeoverPlan older = plan_takeover("s", mine(recipe(3), 20000), "f", former(recipe(7), 10000));
  EXPECT_EQ(older.action, TakeoverPlan::Action::rebuild);
  EXPECT_TRUE(older.set_aside);
  EXPECT_EQ(older.request.generation, 7u);
  EXPECT_EQ(plan_takeover("s", mine(recipe(9), 20000), "f", former(recipe(7), 10000)).action,
            TakeoverPlan::Action::keep);
}

TEST(TakeoverPlan, AnOwnCopyOfTheSameRoadmapIsExtendedToWhatTheFormerOwnerAccepted) {
  const TakeoverPlan plan = plan_takeover("s", mine(recipe(7), 12000), "f", former(recipe(7), 30000));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::extend);
  EXPECT_EQ(plan.extend_by, 18000u);
  EXPECT_FALSE(plan.set_aside);
}

TEST(TakeoverPlan, WithoutACopyTheFormerRoadmapIsRebuiltUnderItsOwnGeneration) {
  const TakeoverPlan plan = plan_takeover("s", mine(std::nullopt, 0), "f", former(recipe(7, 3), 5000));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::rebuild);
  EXPECT_EQ(plan.request.generation, 7u);
  EXPECT_EQ(plan.request.seed, 3u);
  EXPECT_EQ(plan.request.samples, 5000u);
  EXPECT_FALSE(plan.request.replace);
  EXPECT_FALSE(plan.set_aside);
}

TEST(TakeoverPlan, AnOlderCopyOfAnotherRoadmapIsSetAsideNotDeleted) {
  const TakeoverPlan plan = plan_takeover("s", mine(recipe(5, 2), 40000), "f", former(recipe(7, 3), 5000));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::rebuild);
  EXPECT_TRUE(plan.set_aside);
  EXPECT_TRUE(plan.request.replace);
  EXPECT_NE(plan.outcome.find("older copy (generation 5, 40000 samples) is set aside"), std::string::npos)
      << plan.outcome;
}

TEST(TakeoverPlan, ANewerCopyOfAnotherRoadmapIsKept) {
  const TakeoverPlan plan = plan_takeover("s", mine(recipe(9, 2), 100), "f", former(recipe(7, 3), 5000));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::keep);
  EXPECT_FALSE(plan.set_aside);
  EXPECT_NE(plan.outcome.find("later build"), std::string::npos) << plan.outcome;
}

TEST(TakeoverPlan, AnotherSceneFileOrBuilderVersionIsRefusedByName) {
  FormerRoadmap other_file = former(recipe(7), 5000);
  other_file.fingerprint.assign(1, 'g');
  TakeoverPlan plan = plan_takeover("s", mine(recipe(5, 2), 40000), "f", other_file);
  EXPECT_TRUE(plan.refused);
  EXPECT_EQ(plan.action, TakeoverPlan::Action::keep);
  EXPECT_FALSE(plan.set_aside);
  EXPECT_NE(plan.outcome.find("scene file differs from daemon o's (fingerprint g there, f here)"), std::string::npos)
      << plan.outcome;
  FormerRoadmap other_builder = former(recipe(7), 5000);
  other_builder.builder_version = kBuilderVersion + 1;
  plan = plan_takeover("s", mine(std::nullopt, 0), "f", other_builder);
  EXPECT_TRUE(plan.refused);
  EXPECT_NE(plan.outcome.find("made by builder version"), std::string::npos) << plan.outcome;
}

TEST(TakeoverPlan, AFormerOwnerWithoutARoadmapLeavesTheSceneAsItIsHere) {
  const TakeoverPlan plan = plan_takeover("s", mine(recipe(5), 400), "f", former(std::nullopt, 0));
  EXPECT_EQ(plan.action, TakeoverPlan::Action::keep);
  EXPECT_FALSE(plan.set_aside);
  // It dropped its roadmap before this copy was built: the copy is newer, and stays.
  FormerRoadmap dropped_earlier = former(std::nullopt, 0);
  dropped_earlier.generation = 4;
  EXPECT_FALSE(plan_takeover("s", mine(recipe(5), 400), "f", dropped_earlier).set_aside);
}

// A drop is a copy of its generation with no samples: a later drop on the former owner sets this
// daemon's earlier copy aside (the dropped roadmap is not served again), and a later drop here
// keeps the former owner's earlier roadmap from being rebuilt.
TEST(TakeoverPlan, ALaterDropOnEitherSideWinsOverAnEarlierBuild) {
  FormerRoadmap dropped = former(std::nullopt, 0);
  dropped.generation = 9;
  const TakeoverPlan aside = plan_takeover("s", mine(recipe(5), 400), "f", dropped);
  EXPECT_EQ(aside.action, TakeoverPlan::Action::keep);
  EXPECT_TRUE(aside.set_aside);
  EXPECT_NE(aside.outcome.find("dropped its roadmap (generation 9)"), std::string::npos) << aside.outcome;
  service::SessionStatus dropped_here = mine(std::nullopt, 0);
  dropped_here.generation = 9;
  const TakeoverPlan kept = plan_takeover("s", dropped_here, "f", former(recipe(5), 400));
  EXPECT_EQ(kept.action, TakeoverPlan::Action::keep);
  EXPECT_FALSE(kept.set_aside);
  EXPECT_NE(kept.outcome.find("this daemon dropped the scene's roadmap (generation 9)"), std::string::npos)
      << kept.outcome;
  // A build after the drop here is continued as any other.
  EXPECT_EQ(plan_takeover("s", dropped_here, "f", former(recipe(11), 400)).action, TakeoverPlan::Action::rebuild);
}

// Tasks: a rebuild carries the former owner's tasks when they all reached this daemon, and says
// which; a copy lacking some of them is set aside and rebuilt with them; tasks that did not
// arrive are named by their count, and the copy is continued or rebuilt without them.
TEST(TakeoverPlan, TheFormerOwnersTasksAreCarriedOrTheirAbsenceNamed) {
  FormerRoadmap with_tasks = former(recipe(7), 3000);
  with_tasks.task_events = 3;
  with_tasks.tasks = std::vector<service::InspectionTask>{{"a", {Vec3(0, 0, 0)}, true}, {"b", {Vec3(1, 0, 0)}, false}};
  const TakeoverPlan rebuild = plan_takeover("s", mine(std::nullopt, 0), "f", with_tasks);
  EXPECT_EQ(rebuild.action, TakeoverPlan::Action::rebuild);
  ASSERT_EQ(rebuild.tasks.size(), 2u);
  EXPECT_TRUE(rebuild.tasks[0].removed);
  EXPECT_NE(rebuild.outcome.find("with its 2 tasks (b)"), std::string::npos) << rebuild.outcome;

  service::SessionStatus lacking = mine(recipe(7), 3000);
  lacking.task_events = 1;
  const TakeoverPlan aside = plan_takeover("s", lacking, "f", with_tasks);
  EXPECT_EQ(aside.action, TakeoverPlan::Action::rebuild) << aside.outcome;
  EXPECT_TRUE(aside.set_aside);
  EXPECT_EQ(aside.tasks.size(), 2u);
  EXPECT_NE(aside.outcome.find("1 task events of 3) is set aside"), std::string::npos) << aside.outcome;

  lacking.task_events = 3;  // the same tasks here: continued as any copy of the same roadmap
  EXPECT_EQ(plan_takeover("s", lacking, "f", with_tasks).action, TakeoverPlan::Action::keep);

  FormerRoadmap unknown = with_tasks;
  unknown.tasks.reset();
  const TakeoverPlan without = plan_takeover("s", mine(std::nullopt, 0), "f", unknown);
  EXPECT_EQ(without.action, TakeoverPlan::Action::rebuild);
  EXPECT_TRUE(without.tasks.empty());
  EXPECT_NE(without.outcome.find("its tasks (3 events) did not reach this daemon"), std::string::npos)
      << without.outcome;
  lacking.task_events = 0;
  const TakeoverPlan continued = plan_takeover("s", lacking, "f", unknown);
  EXPECT_EQ(continued.action, TakeoverPlan::Action::keep);
  EXPECT_NE(continued.outcome.find("had 3 task events to this copy's 0"), std::string::npos) << continued.outcome;
}

}  // namespace
}  // namespace ispars::server
