// A session's record (SessionRecord) alone, with no builder and no store: what each step of a
// session's life makes of its status, and what it refuses by name without changing anything.

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ispars/params/input_error.hpp"
#include "ispars/service/session_record.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

class SessionRecordTest : public ::testing::Test {
 protected:
  static const planning::Scene& scene() { return test::shared_scene("demo_tank_tower"); }
  static RoadmapRecipe recipe(std::uint64_t samples = 500) {
    return requested_recipe("tower", scene(), request(samples), SessionLimits{});
  }
  static BuildRequest request(std::uint64_t samples, bool replace = false) {
    BuildRequest r;
    r.method = BuildMethod::ispars;
    r.samples = samples;
    r.replace = replace;
    return r;
  }
  // The field of the InputError `f` throws ("" when it throws none).
  template <typename F>
  static std::string refused_field(F&& f) {
    try {
      f();
    } catch (const params::InputError& e) {
      return e.field();
    }
    return "";
  }
  // A record with a roadmap of `samples` samples, as a build's first chunk leaves it.
  void build(std::uint64_t samples) {
    record_.accept_build(recipe(samples), request(samples, true), {});
    bool changed = false;
    const std::optional<SessionJob> job = record_.take(false, changed);
    ASSERT_TRUE(job);
    record_.start(*job);
    PublishedRoadmap copy =
        make_published(std::make_shared<const Roadmap>(scene().pois().size()), job->recipe.generation, samples);
    record_.record_chunk({job->build, samples, samples, std::move(copy), {}});
    record_.end_job(false);
    record_.forget_starting(false);
  }
  SessionRecord record_{"tower", scene(), [this](const SessionStatus& s) { notified_.push_back(s); }};
  std::vector<SessionStatus> notified_;
};

TEST_F(SessionRecordTest, AnAcceptedBuildShowsAsAcceptedUntilItsFirstChunkIsRecorded) {
  EXPECT_EQ(record_.status().state, SessionState::empty);
  const std::uint64_t generation = record_.accept_build(recipe(), request(500), {});
  SessionStatus s = record_.status();
  EXPECT_EQ(s.state, SessionState::queued);
  ASSERT_TRUE(s.accepted);
  EXPECT_EQ(s.accepted->generation, generation);
  EXPECT_EQ(s.samples_target, 500u);
  ASSERT_EQ(notified_.size(), 1u);
  EXPECT_TRUE(record_.busy());

  bool changed = true;
  const std::optional<SessionJob> job = record_.take(false, changed);
  ASSERT_TRUE(job);
  EXPECT_FALSE(changed);
  ASSERT_TRUE(job->build);
  EXPECT_EQ(job->recipe.generation, generation);
  record_.start(*job);
  EXPECT_TRUE(record_.status().accepted) << "a started build is accepted until its first commit";
  record_.record_chunk({job->build, 500, 64, std::nullopt, {12, 40}});
  s = record_.status();
  EXPECT_FALSE(s.accepted);
  ASSERT_TRUE(s.recipe);
  EXPECT_EQ(s.samples_done, 64u);
  EXPECT_EQ(s.samples_target, 500u);
  EXPECT_EQ(s.dense_vertices, 12u);
  EXPECT_EQ(s.dense_edges, 40u);
  record_.end_job(false);
  s = record_.status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.samples_target, 64u) << "a job that ended short has its target set to what it reached";
}

TEST_F(SessionRecordTest, RequestsThatCannotStartAreRefusedByNameAndChangeNothing) {
  EXPECT_EQ(refused_field([&] { record_.accept_extend(100, {}); }), "scene") << "no roadmap to extend";
  ASSERT_NO_FATAL_FAILURE(build(300));
  EXPECT_EQ(refused_field([&] { record_.accept_build(recipe(), request(500), {}); }), "replace");
  const SessionStatus before = record_.status();
  const std::size_t notes = notified_.size();
  const auto refuse = [](const planning::Scene&, const RoadmapRecipe&, std::uint64_t) {
    throw params::InputError("request", "samples", "too much memory");
  };
  EXPECT_EQ(refused_field([&] { record_.accept_extend(100, refuse); }), "samples");
  EXPECT_EQ(refused_field([&] {
              record_.accept_build(recipe(), request(500, true),
                                   [] { throw params::InputError("request", "samples", "too much memory"); });
            }),
            "samples");
  const SessionStatus after = record_.status();
  EXPECT_EQ(after.state, before.state);
  EXPECT_EQ(after.samples_target, before.samples_target);
  EXPECT_FALSE(after.accepted);
  EXPECT_EQ(notified_.size(), notes) << "a refusal announced a status";

  std::uint64_t admitted = 0;
  EXPECT_EQ(record_.accept_extend(
                200, [&](const planning::Scene&, const RoadmapRecipe&, std::uint64_t samples) { admitted = samples; }),
            500u);
  EXPECT_EQ(admitted, 500u) << "an extend is admitted at the samples it reaches";
  EXPECT_EQ(refused_field([&] { record_.accept_extend(100, {}); }), "scene") << "a second job while one is queued";
  EXPECT_EQ(refused_field([&] { record_.begin_discard(); }), "scene") << "a drop while a job is queued";
}

TEST_F(SessionRecordTest, ACancelDequeuesAQueuedJobAndSignalsARunningOne) {
  EXPECT_EQ(record_.cancel(), CancelReach::none);
  ASSERT_NO_FATAL_FAILURE(build(300));
  record_.accept_extend(200, {});
  EXPECT_EQ(record_.cancel(), CancelReach::dequeued);
  SessionStatus s = record_.status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.samples_target, 300u);
  EXPECT_EQ(s.last_error, "cancelled before it started");
  bool changed = true;
  EXPECT_FALSE(record_.take(false, changed)) << "a dequeued job was still taken";
  EXPECT_FALSE(changed);

  record_.accept_extend(200, {});
  ASSERT_TRUE(record_.take(false, changed));
  EXPECT_EQ(record_.cancel(), CancelReach::signalled);
  EXPECT_TRUE(record_.cancelled());
  record_.end_job(false);
  s = record_.status();
  EXPECT_FALSE(record_.cancelled()) << "the next job would start cancelled";
  EXPECT_EQ(s.last_error, "cancelled at 300 of 500 samples");

  record_.accept_extend(200, {});
  ASSERT_FALSE(record_.take(true, changed)) << "a stopping daemon took a queued job";
  EXPECT_TRUE(changed);
  EXPECT_EQ(record_.status().last_error, "daemon stopped before the job started");
}

TEST_F(SessionRecordTest, AFailureShowsWhatTheStoreHoldsAndATaskFailureOnlyLeavesTheSceneIdle) {
  ASSERT_NO_FATAL_FAILURE(build(300));
  record_.fail("task 'welds' not added: cancelled");
  EXPECT_EQ(record_.status().state, SessionState::failed);
  record_.settle_failure("task 'welds' not added: cancelled");
  EXPECT_EQ(record_.status().state, SessionState::idle);
  record_.fail("task 'welds' not added: x; reopening the store failed: y");
  record_.settle_failure("task 'welds' not added: x");
  EXPECT_EQ(record_.status().state, SessionState::failed) << "a failure with more to it than the task's was settled";

  // A failed job whose store could not be read: the scene shows no roadmap, and says why.
  record_.take_stored(std::nullopt, SessionState::failed, "the store is gone");
  const SessionStatus s = record_.status();
  EXPECT_EQ(s.state, SessionState::failed);
  EXPECT_FALSE(s.recipe);
  EXPECT_EQ(s.samples_done, 0u);
  EXPECT_EQ(s.vertices, 0u);
  EXPECT_EQ(s.last_error, "the store is gone");
}

TEST_F(SessionRecordTest, ADropsGenerationIsNewerThanTheRoadmapItDiscards) {
  ASSERT_NO_FATAL_FAILURE(build(300));
  const std::uint64_t built = record_.published().generation;
  const std::uint64_t empty = record_.begin_discard();
  EXPECT_GT(empty, built);
  EXPECT_EQ(refused_field([&] { record_.accept_extend(100, {}); }), "scene") << "a request during a drop";
  record_.end_discard();
  EXPECT_EQ(record_.accept_extend(100, {}), 400u) << "a failed drop left the record refusing requests";
  EXPECT_EQ(record_.cancel(), CancelReach::dequeued);
  record_.discarded(record_.begin_discard());
  const SessionStatus s = record_.status();
  EXPECT_EQ(s.state, SessionState::empty);
  EXPECT_FALSE(s.recipe);
  EXPECT_GT(s.generation, built);
  // A later build is newer than the drop.
  EXPECT_GT(record_.accept_build(recipe(), request(100), {}), s.generation);
}

TEST_F(SessionRecordTest, ARefusedStoreNamesItsDamageAndAClosedRecordRefusesEverything) {
  record_.refuse("snapshot.bin is damaged at byte 8");
  EXPECT_EQ(record_.status().state, SessionState::failed);
  try {
    record_.accept_build(recipe(), request(500), {});
    FAIL() << "a build over a damaged store without replace was accepted";
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.field(), "replace");
    EXPECT_NE(std::string(e.what()).find("snapshot.bin is damaged"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(record_.accept_build(recipe(), request(500, true), {}));
  EXPECT_EQ(refused_field([&] { record_.close(); }), "scene") << "closed while a job is queued";
  EXPECT_EQ(record_.cancel(), CancelReach::dequeued);
  record_.close();
  EXPECT_EQ(refused_field([&] { record_.accept_build(recipe(), request(500, true), {}); }), "scene");
}

}  // namespace
}  // namespace ispars::service
