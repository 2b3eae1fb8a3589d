// A scene's roadmap session: jobs, cancellation, stopping, recovery and refusals.

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "roadmap_session_fixture.hpp"
#include "support/eventually.hpp"

namespace ispars::service {
namespace {

TEST_F(RoadmapSessionTest, AJobCommitsBatchesThatReplayToThePublishedRoadmap) {
  Roadmap replica(scene().pois().size());
  std::uint64_t generation = 0;
  std::size_t statuses = 0;
  SessionCallbacks callbacks;
  callbacks.on_commit = [&](const RoadmapBatch& batch, std::uint64_t g, std::uint64_t, std::size_t) {
    generation = g;
    apply_batch(replica, batch);
  };
  callbacks.on_status = [&](const SessionStatus&) { ++statuses; };
  auto session = open(callbacks);
  EXPECT_EQ(session->status().state, SessionState::empty);
  session->request_build(ispars(4000, 3));
  EXPECT_EQ(session->status().state, SessionState::queued);
  session->run_job(never_);
  const SessionStatus s = session->status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.samples_done, 4000u);
  const PublishedRoadmap p = session->published();
  EXPECT_EQ(p.generation, generation);
  EXPECT_EQ(roadmap_digest(replica), roadmap_digest(*p.roadmap));
  EXPECT_EQ(roadmap_digest(*p.roadmap), uninterrupted_digest(scene(), 4000, 3));
  EXPECT_GE(statuses, 3u);
  const planning::VerificationReport report = session->verify(kVerifyBudget);
  EXPECT_TRUE(report.geometry_ok());
  EXPECT_EQ(report.invariant_violations, 0u);
}

TEST_F(RoadmapSessionTest, BuildThreadsAndTheVariantReachTheBuilder) {
  // Two threads per build give the one-thread roadmap; the request's rule set is the recipe's.
  SessionLimits limits;
  limits.build_threads = 2;
  auto session = open({}, limits);
  BuildRequest request = ispars(3000, 5);
  request.variant = SparsVariant::alg1;
  session->request_build(request);
  session->run_job(never_);
  ASSERT_TRUE(session->status().recipe);
  EXPECT_EQ(session->status().recipe->variant, SparsVariant::alg1);
  planning::BuildOptions options;
  options.seed = 5;
  options.variant = SparsVariant::alg1;
  auto b = planning::make_roadmap_builder(BuildMethod::ispars, scene(), options);
  b->extend(3000);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), roadmap_digest(b->roadmap()));
  EXPECT_NE(roadmap_digest(b->roadmap()), uninterrupted_digest(scene(), 3000, 5)) << "the variants differ here";
}

TEST_F(RoadmapSessionTest, ReadersOnOtherThreadsSeeConsistentVersionsWhileAJobRuns) {
  auto session = open();
  session->request_build(ispars(busy_samples(), 2));
  std::atomic<bool> done{false};
  std::atomic<std::size_t> reads{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < 2; ++r) {
    readers.emplace_back([&] {
      std::uint64_t last = 0;
      while (!done) {
        const PublishedRoadmap p = session->published();
        const SessionStatus s = session->status();
        EXPECT_GE(p.roadmap->version(), last);  // versions never go back
        std::uint64_t changes = 0;
        p.roadmap->for_each_change(0, UINT64_MAX, [&](const RoadmapChange&) { ++changes; });
        EXPECT_EQ(p.roadmap->version(), changes);
        last = p.roadmap->version();
        (void)s;
        ++reads;
      }
    });
  }
  session->run_job(never_);
  done = true;
  for (auto& t : readers) t.join();
  EXPECT_GT(reads.load(), 0u);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), uninterrupted_digest(scene(), busy_samples(), 2));
}

// A store damaged beyond a torn tail: the scene loads FAILED with the damage as its last error,
// nothing is read, cut or rebuilt implicitly; drop (or build with replace) discards it explicitly.
TEST_F(RoadmapSessionTest, ADamagedStoreLoadsFailedAndIsDiscardedOnlyWhenAsked) {
  {
    auto session = open();
    session->request_build(ispars(1500, 3));
    session->run_job(never_);
  }
  const auto snapshot = dir_.path() / "tower" / "snapshot.bin";
  const auto journal = dir_.path() / "tower" / "journal.log";
  write_file_atomically(snapshot, "ISPSNP01 damaged");
  const auto bytes_of = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  const std::string journal_before = bytes_of(journal);
  auto session = open();
  EXPECT_EQ(session->status().state, SessionState::failed);
  EXPECT_NE(session->status().last_error.find("snapshot.bin is damaged"), std::string::npos)
      << session->status().last_error;
  EXPECT_EQ(session->published().roadmap->vertex_count(), 0u);
  EXPECT_THROW(session->request_build(ispars(800, 3)), params::InputError);  // without replace
  EXPECT_THROW(session->request_extend(100), params::InputError);
  EXPECT_EQ(bytes_of(snapshot), "ISPSNP01 damaged");
  EXPECT_EQ(bytes_of(journal), journal_before);
  session->drop();
  EXPECT_EQ(session->status().state, SessionState::empty);
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "tower"));
  session->request_build(ispars(800, 3));
  session->run_job(never_);
  EXPECT_EQ(session->status().state, SessionState::idle) << session->status().last_error;
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), uninterrupted_digest(scene(), 800, 3));
}

// The scene changed since its roadmap was built (here its delta): the stored roadmap is not
// served, replayed or extended, and stays on disk until a rebuild with replace.
TEST_F(RoadmapSessionTest, ARoadmapOfAnotherVersionOfTheSceneLoadsFailedUntilRebuilt) {
  {
    auto session = open();
    session->request_build(ispars(1200, 5));
    session->run_job(never_);
    ASSERT_EQ(session->status().state, SessionState::idle);
  }
  const scene_files::SceneConfig& c = scene().config();
  const planning::Scene edited =
      scene().with_roadmap_parameters(c.dense_delta * 0.9, c.sparse_delta, c.stretch, "edited");
  auto session =
      std::make_unique<RoadmapSession>("tower", edited, dir_.path() / "tower", SessionLimits{}, SessionCallbacks{});
  EXPECT_EQ(session->status().state, SessionState::failed);
  EXPECT_NE(session->status().last_error.find("was built on another version of the scene"), std::string::npos)
      << session->status().last_error;
  EXPECT_EQ(session->published().roadmap->vertex_count(), 0u);
  EXPECT_THROW(session->request_extend(100), params::InputError);
  EXPECT_THROW(session->request_build(ispars(800, 5)), params::InputError);
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "tower" / "recipe.json"));
  BuildRequest replace = ispars(800, 5);
  replace.replace = true;
  session->request_build(replace);
  session->run_job(never_);
  EXPECT_EQ(session->status().state, SessionState::idle) << session->status().last_error;
  // Reopened on the edited scene, the new roadmap is served.
  session.reset();
  session =
      std::make_unique<RoadmapSession>("tower", edited, dir_.path() / "tower", SessionLimits{}, SessionCallbacks{});
  EXPECT_EQ(session->status().state, SessionState::idle) << session->status().last_error;
}

TEST_F(RoadmapSessionTest, CancelStopsAfterTheCurrentChunk) {
  RoadmapSession* raw = nullptr;
  SessionCallbacks callbacks;
  callbacks.on_commit = [&](const RoadmapBatch&, std::uint64_t, std::uint64_t samples, std::size_t) {
    if (samples > 0) raw->cancel();
  };
  auto session = open(callbacks);
  raw = session.get();
  EXPECT_FALSE(session->cancel());  // nothing to cancel
  session->request_build(ispars(1'000'000));
  session->run_job(never_);
  const SessionStatus s = session->status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_LT(s.samples_done, 1'000'000u);
  EXPECT_EQ(s.samples_target, s.samples_done);
  EXPECT_NE(s.last_error.find("cancelled"), std::string::npos);
}

TEST_F(RoadmapSessionTest, VerifyAndDropRightAfterAJobTurnsIdleWaitForItsLastStatus) {
  // The job reports idle, then still holds the builder while its last status goes out (over DDS in
  // the daemon, which can be slow). A verify or drop that sees idle at that moment must wait for it,
  // not answer "a build is running" (CI saw exactly that).
  std::atomic<bool> idle_seen{false};
  SessionCallbacks callbacks;
  callbacks.on_status = [&](const SessionStatus& s) {
    if (s.state != SessionState::idle || s.samples_done == 0) return;
    idle_seen = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // a slow status reader's work
  };
  auto session = open(callbacks);
  session->request_build(ispars(500));
  std::thread job([&] { session->run_job(never_); });
  ASSERT_TRUE(test::eventually([&] { return idle_seen.load(); }, std::chrono::seconds(30), "the idle status",
                               std::chrono::milliseconds(1)));
  EXPECT_EQ(session->status().state, SessionState::idle);
  EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
  job.join();
  // A queued job is still refused by name.
  session->request_extend(100);
  EXPECT_THROW((void)session->verify(kVerifyBudget), params::InputError);
  EXPECT_THROW(session->drop(), params::InputError);
  session->run_job(never_);
  idle_seen = false;
  session->request_extend(100);
  std::thread again([&] { session->run_job(never_); });
  ASSERT_TRUE(test::eventually([&] { return idle_seen.load(); }, std::chrono::seconds(30), "the idle status again",
                               std::chrono::milliseconds(1)));
  session->drop();
  again.join();
  EXPECT_EQ(session->status().state, SessionState::empty);
}

TEST_F(RoadmapSessionTest, CancellingAQueuedReplaceKeepsTheOldRoadmap) {
  auto session = open();
  session->request_build(ispars(800));
  session->run_job(never_);
  const std::uint64_t before = roadmap_digest(*session->published().roadmap);
  BuildRequest replace = ispars(5000, 2);
  replace.replace = true;
  session->request_build(replace);
  EXPECT_EQ(session->status().recipe->seed, 1u);  // still the current roadmap's recipe
  EXPECT_TRUE(session->cancel());
  session->run_job(never_);
  const SessionStatus s = session->status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.samples_done, 800u);
  EXPECT_EQ(s.recipe->seed, 1u);
  EXPECT_EQ(s.last_error, "cancelled before it started");
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), before);
}

TEST_F(RoadmapSessionTest, AClosedSessionAcceptsNoJobs) {
  auto session = open();
  session->request_build(ispars(100));
  EXPECT_THROW(session->close(), params::InputError);  // queued
  session->run_job(never_);
  session->close();
  EXPECT_THROW(session->request_extend(10), params::InputError);
  EXPECT_THROW(session->request_build(ispars(10)), params::InputError);
}

TEST_F(RoadmapSessionTest, BadAndConflictingRequestsAreRefusedByName) {
  SessionLimits limits;
  limits.max_samples = 10'000;
  auto session = open({}, limits);
  const auto expect_refusal = [](const auto& f, const std::string& needle) {
    try {
      f();
      ADD_FAILURE() << "no error for " << needle;
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_refusal([&] { session->request_extend(10); }, "has no roadmap to extend");
  expect_refusal([&] { session->request_extend(0); }, "samples: must be at least 1");
  expect_refusal([&] { session->request_build(ispars(20'000)); }, "samples: 20000 is more than");
  expect_refusal([&] { (void)session->path(Vec3(0, 0, 1), Vec3(1, 1, 1)); }, "has no roadmap yet");
  expect_refusal([&] { session->drop(); }, "has no roadmap");
  BuildRequest r = ispars(100);
  r.overrides.sparse_delta = -2.0;
  expect_refusal([&] { session->request_build(r); }, "sparse_delta: must be in (0, 1000000], got -2");
  r.overrides = {};
  r.overrides.stretch = 0.5;
  expect_refusal([&] { session->request_build(r); }, "stretch: must be in [1, 100], got 0.5");
  r.overrides = {};
  r.overrides.dense_delta = 1e-6;
  expect_refusal([&] { session->request_build(r); }, "overrides.dense_delta: 1e-06 is too small for this scene");
  r.overrides = {};
  r.overrides.sparse_delta = 1e5;
  expect_refusal([&] { session->request_build(r); },
                 "overrides.sparse_delta: 100000 is larger than the scene's diagonal");
  r.overrides = {};
  r.overrides.stretch_slack = 0.5;
  r.method = BuildMethod::dense;
  expect_refusal([&] { session->request_build(r); }, "overrides.stretch_slack: 0.5 given, but dense method has no");
  r.method = BuildMethod::ispars;
  r.variant = SparsVariant::alg1;
  expect_refusal([&] { session->request_build(r); }, "but ispars variant alg1 has no stretch rules");
  r.variant = SparsVariant::stretch;
  r.overrides = {};
  r.overrides.stretch_slack_after = 1000;
  expect_refusal([&] { session->request_build(r); },
                 "overrides.stretch_slack_after: 1000 given, but there is no stretch_slack to start there");
  EXPECT_EQ(session->status().state, SessionState::empty);  // nothing changed

  session->request_build(ispars(500));
  expect_refusal([&] { session->request_build(ispars(500)); }, "already running");
  expect_refusal([&] { session->request_extend(5); }, "already running");
  session->run_job(never_);
  expect_refusal([&] { session->request_build(ispars(500)); }, "replace: scene 'tower' already has a roadmap");
  BuildRequest replace = ispars(300, 2);
  replace.replace = true;
  replace.overrides.sparse_delta = 4.0;
  const auto old_generation = session->published().generation;
  session->request_build(replace);
  session->run_job(never_);
  EXPECT_NE(session->published().generation, old_generation);
  EXPECT_EQ(session->status().recipe->sparse_delta, 4.0);
  session->drop();
  EXPECT_EQ(session->status().state, SessionState::empty);
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "tower"));
}

TEST_F(RoadmapSessionTest, PathsAreFreeJoinedWithinDeltaAndMeasured) {
  auto session = open();
  session->request_build(ispars(6000));
  session->run_job(never_);
  const planning::Scene& s = scene();
  const auto p = session->published();
  const double radius = s.config().sparse_delta;
  scene_files::Rng rng(5);
  int answered = 0;
  for (int i = 0; i < 40; ++i) {
    const Vec3 a = s.sample_valid_configuration(rng);
    const Vec3 b = s.sample_valid_configuration(rng);
    try {
      const planning::RoadmapPath path = session->path(a, b);
      ++answered;
      ASSERT_GE(path.waypoints.size(), 2u);
      EXPECT_EQ(path.waypoints.front(), a);
      EXPECT_EQ(path.waypoints.back(), b);
      double length = 0;
      for (std::size_t k = 1; k < path.waypoints.size(); ++k) {
        EXPECT_TRUE(s.segment_valid(path.waypoints[k - 1], path.waypoints[k]));
        length += (path.waypoints[k] - path.waypoints[k - 1]).norm();
      }
      EXPECT_NEAR(path.length, length, 1e-9);
      if (!path.vertices.empty()) {
        EXPECT_LE((p.roadmap->position(path.vertices.front()) - a).norm(), radius);
        EXPECT_LE((p.roadmap->position(path.vertices.back()) - b).norm(), radius);
        for (std::size_t k = 1; k < path.vertices.size(); ++k) {
          EXPECT_TRUE(p.roadmap->has_edge(path.vertices[k - 1], path.vertices[k]));
        }
      }
    } catch (const params::InputError& e) {
      // Only the documented refusals: no free join within Delta, or different components.
      const std::string what = e.what();
      EXPECT_TRUE(what.find("no free segment") != std::string::npos ||
                  what.find("different component") != std::string::npos)
          << what;
    }
  }
  EXPECT_GT(answered, 10);
  EXPECT_THROW((void)session->path(Vec3(std::nan(""), 0, 0), Vec3(0, 0, 1)), params::InputError);
  EXPECT_THROW((void)session->path(Vec3(0, 0, 1), Vec3(1e6, 0, 0)), params::InputError);
}

// A Dense session drops its builder when a job ends (the published copy is the last commit) and
// resumes it from that copy for the next job: verify and extend work as if it had kept it.
TEST_F(RoadmapSessionTest, ADenseSessionResumesFromItsPublishedRoadmapBetweenJobs) {
  auto session = open();
  BuildRequest dense = ispars(1500, 4);
  dense.method = BuildMethod::dense;
  session->request_build(dense);
  session->run_job(never_);
  EXPECT_TRUE(session->verify(kVerifyBudget).geometry_ok());
  session->request_extend(700);
  session->run_job(never_);
  EXPECT_EQ(session->status().samples_done, 2200u);
  planning::BuildOptions options;
  options.seed = 4;
  const auto reference = planning::make_roadmap_builder(BuildMethod::dense, scene(), options);
  reference->extend(2200);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), roadmap_digest(reference->roadmap()));
  EXPECT_TRUE(session->verify(kVerifyBudget).geometry_ok());
}

}  // namespace
}  // namespace ispars::service
