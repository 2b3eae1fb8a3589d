// A session's build job (BuildJob): on a record of its own, what a build commits, records and
// announces, and how a failure is recorded; through a session, how a builder comes back after a
// restart, and what readers are served when a job ends.

#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>

#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/service/build_job.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "roadmap_session_fixture.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

// A job over a record of its own, with no session around it.
struct JobBench {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  test::TempDir dir;
  const std::string name = "tower";
  const std::filesystem::path store_dir = dir.path() / "tower";
  const SessionLimits limits;
  SessionRecord record{name, scene, {}};

  void accept(std::uint64_t samples, std::uint64_t seed) {
    BuildRequest request;
    request.method = BuildMethod::ispars;
    request.samples = samples;
    request.seed = seed;
    record.accept_build(requested_recipe(name, scene, request, limits), request, {});
  }
};

// Each chunk is durable before the record shows it, and recorded before it is announced: a
// follower told of a batch finds it in the status and the store, and the batches rebuild the
// roadmap readers are served.
TEST(BuildJob, EachChunkIsStoredThenRecordedThenAnnounced) {
  JobBench b;
  Roadmap replica(b.scene.pois().size());
  std::size_t batches = 0;
  BuildJob job(JobSite{b.name, b.scene, b.store_dir, b.limits, disk()}, b.record,
               [&](const RoadmapBatch& batch, std::uint64_t, std::uint64_t samples, std::size_t poi_count) {
                 ++batches;
                 EXPECT_EQ(poi_count, b.scene.pois().size());
                 EXPECT_EQ(b.record.status().samples_done, samples) << "announced before it was recorded";
                 EXPECT_EQ(RoadmapStore::read(b.store_dir, b.scene.pois().size()).roadmaps.samples, samples)
                     << "announced before it was stored";
                 apply_batch(replica, batch);
               });
  job.run(std::atomic<bool>{false});
  EXPECT_EQ(batches, 0u) << "a job ran with nothing queued";
  EXPECT_EQ(job.store(), nullptr);
  b.accept(3000, 5);
  job.run(std::atomic<bool>{false});
  const SessionStatus s = b.record.status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.samples_done, 3000u);
  EXPECT_GE(batches, 2u);
  const std::uint64_t digest = uninterrupted_digest(b.scene, 3000, 5);
  EXPECT_EQ(roadmap_digest(*b.record.published().roadmap), digest);
  EXPECT_EQ(roadmap_digest(replica), digest);
  ASSERT_NE(job.store(), nullptr);
  const std::optional<RoadmapsView> held = job.roadmaps();
  ASSERT_TRUE(held) << "an ispars builder is kept between jobs";
  EXPECT_EQ(held->samples, 3000u);
}

// A build whose store cannot be made fails, saying why, and the record shows what the directory
// holds: no roadmap.
TEST(BuildJob, AStoreThatCannotBeMadeFailsTheBuildNamedAndTheRecordAgrees) {
  JobBench b;
  { std::ofstream(b.dir.path() / "not-a-dir") << "x"; }
  const std::filesystem::path blocked = b.dir.path() / "not-a-dir" / "tower";
  BuildJob job(JobSite{b.name, b.scene, blocked, b.limits, disk()}, b.record, {});
  b.accept(500, 1);
  job.run(std::atomic<bool>{false});
  const SessionStatus s = b.record.status();
  EXPECT_EQ(s.state, SessionState::failed);
  EXPECT_FALSE(s.recipe);
  EXPECT_EQ(s.vertices, 0u);
  EXPECT_NE(s.last_error.find("not-a-dir"), std::string::npos) << s.last_error;
  EXPECT_EQ(job.store(), nullptr);
  EXPECT_FALSE(job.roadmaps());
  EXPECT_FALSE(b.record.busy());
}

// A cancel that lands just after a commit whose chunk took no copy for readers (the copy is
// decided before the cancel, and only every quarter second or so) ends the loop there: readers
// must still get that last commit, as the status's samples say. CI's kill -9 campaign saw a
// snapshot one chunk older than the status after such a cancel.
TEST(BuildJob, ACancelRightAfterACommitLeavesReadersThatCommitNotAnOlderOne) {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  for (const BuildMethod method : {BuildMethod::ispars, BuildMethod::dense, BuildMethod::ispars2}) {
    SCOPED_TRACE(std::string(to_string(method)));
    test::TempDir dir;
    std::unique_ptr<RoadmapSession> session;
    int commits = 0;
    SessionCallbacks callbacks;
    callbacks.on_commit = [&](const RoadmapBatch&, std::uint64_t, std::uint64_t, std::size_t) {
      if (++commits == 3) {
        EXPECT_TRUE(session->cancel());  // after the first chunk's copy, within a second
      }
    };
    session = std::make_unique<RoadmapSession>("tower", scene, dir.path() / "tower", SessionLimits{}, callbacks);
    BuildRequest request;
    request.method = method;
    request.samples = 100'000;
    request.seed = 4;
    session->request_build(request);
    std::atomic<bool> never{false};
    session->run_job(never);
    const SessionStatus status = session->status();
    ASSERT_EQ(status.state, SessionState::idle);
    ASSERT_EQ(commits, 3);
    ASSERT_LT(status.samples_done, 100'000u);
    const PublishedRoadmap published = session->published();
    EXPECT_EQ(published.samples, status.samples_done);
    planning::BuildOptions options;
    options.seed = 4;
    auto reference = planning::make_roadmap_builder(method, scene, options);
    reference->extend(status.samples_done);
    EXPECT_EQ(roadmap_digest(*published.roadmap), roadmap_digest(reference->roadmap()))
        << "readers were served an older roadmap than the status's " << status.samples_done << " samples";
  }
}

// A stopped build keeps its committed chunks, and a reopened session goes on exactly. The dense
// pair resumes from its stored roadmaps and never replays; IRIS-C replays its recipe, and a stop
// during that replay leaves the scene idle as it was (not failed).
TEST(BuildJob, AStoppedBuildGoesOnExactlyResumedOrForIrisCReplayed) {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  test::TempDir dir;
  std::atomic<bool> never{false};
  const auto open = [&](SessionCallbacks callbacks, const std::string& store) {
    return std::make_unique<RoadmapSession>("tower", scene, dir.path() / store, SessionLimits{}, std::move(callbacks));
  };
  const auto uninterrupted = [&](std::uint64_t samples, BuildMethod method) {
    return uninterrupted_digest(scene, samples, 9, method);
  };
  for (const BuildMethod method : {BuildMethod::ispars, BuildMethod::irisc}) {
    SCOPED_TRACE(to_string(method));
    const std::string store(to_string(method));
    std::uint64_t stopped_at = 0;
    {
      std::atomic<bool> stopping{false};
      SessionCallbacks callbacks;
      callbacks.on_commit = [&](const RoadmapBatch&, std::uint64_t, std::uint64_t samples, std::size_t) {
        if (samples >= 1000) stopping = true;  // as SIGTERM would, mid-build
      };
      auto session = open(callbacks, store);
      BuildRequest request;
      request.method = method;
      request.samples = 1'000'000;
      request.seed = 9;
      session->request_build(request);
      session->run_job(stopping);
      stopped_at = session->status().samples_done;
      EXPECT_GE(stopped_at, 1000u);
      EXPECT_LT(stopped_at, 1'000'000u);
      EXPECT_NE(session->status().last_error.find("daemon stopped"), std::string::npos);
    }
    std::atomic<bool> stop_replay{false};
    bool replayed = false;
    SessionCallbacks on_replay;
    on_replay.on_status = [&](const SessionStatus& s) {
      if (s.state == SessionState::replaying) replayed = stop_replay = true;  // as SIGTERM would, mid-replay
    };
    auto session = open(on_replay, store);
    EXPECT_NE(session->recovery_note().find("recovered " + store + " roadmap"), std::string::npos);
    EXPECT_EQ(session->status().samples_done, stopped_at);
    EXPECT_EQ(roadmap_digest(*session->published().roadmap), uninterrupted(stopped_at, method));
    if (method == BuildMethod::ispars) {
      EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
    }
    session->request_extend(500);
    session->run_job(stop_replay);
    if (method == BuildMethod::irisc) {
      ASSERT_TRUE(replayed);
      EXPECT_EQ(session->status().state, SessionState::idle);
      EXPECT_NE(session->status().last_error.find("daemon stopped during the replay, at 0 of " +
                                                  std::to_string(stopped_at) + " samples"),
                std::string::npos)
          << session->status().last_error;
      EXPECT_EQ(session->status().samples_done, stopped_at);
      session->request_extend(500);
      session->run_job(never);  // replays the recipe, checks it against the store, then extends
    } else {
      EXPECT_FALSE(replayed) << "the dense pair resumes from its stored roadmaps";
    }
    EXPECT_EQ(session->status().state, SessionState::idle) << session->status().last_error;
    EXPECT_EQ(session->status().samples_done, stopped_at + 500);
    EXPECT_EQ(roadmap_digest(*session->published().roadmap), uninterrupted(stopped_at + 500, method));
    if (method == BuildMethod::ispars) {
      EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
    }
  }
}

// A job is running from the moment a build worker takes it from the queue, before its builder
// is back: a cancel that lands while the builder resumes from the store stops the job, and no
// sample is drawn after it. (The status said "queued" in that window, so the cancel emptied a
// queue the job had already left, and the job then ran to its end: CI's kill -9 campaign found
// "a build is running" right after its cancel.)
TEST(BuildJob, ACancelWhileTheBuilderResumesStopsTheJob) {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  test::TempDir dir;
  std::atomic<bool> never{false};
  BuildRequest request;
  request.method = BuildMethod::ispars;
  request.samples = 30'000;
  request.seed = 2;
  {
    RoadmapSession first("tower", scene, dir.path() / "tower", SessionLimits{}, {});
    first.request_build(request);
    first.run_job(never);
    ASSERT_EQ(first.status().samples_done, 30'000u);
  }
  RoadmapSession session("tower", scene, dir.path() / "tower", SessionLimits{}, {});
  session.request_extend(20'000);
  std::thread job([&] { session.run_job(never); });
  // The worker takes the job within microseconds; resuming 30,000 samples' roadmaps takes far
  // longer than this wait, so the cancel lands while the builder comes back.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the cancel's moment, not a wait
  const bool cancelled = session.cancel();
  job.join();
  EXPECT_TRUE(cancelled);
  const SessionStatus status = session.status();
  EXPECT_EQ(status.state, SessionState::idle) << status.last_error;
  EXPECT_EQ(status.samples_done, 30'000u) << "samples were drawn after the cancel was accepted";
  EXPECT_NE(status.last_error.find("cancelled"), std::string::npos) << status.last_error;
}

// An extend is acknowledged with its target, and the status says so from then on, while it waits
// for a worker (the fleet's announcement and a takeover continue to it: docs/fleet.md); a cancel
// or a stop before it starts takes the target back.
TEST(BuildJob, AQueuedExtendsTargetIsInTheStatusUntilItIsCancelledOrStopped) {
  const planning::Scene& scene = test::shared_scene("demo_tank_tower");
  test::TempDir dir;
  std::atomic<bool> never{false};
  RoadmapSession session("tower", scene, dir.path() / "tower", SessionLimits{}, {});
  BuildRequest request;
  request.method = BuildMethod::ispars;
  request.samples = 300;
  request.seed = 2;
  session.request_build(request);
  session.run_job(never);
  EXPECT_EQ(session.request_extend(500), 800u);
  SessionStatus queued = session.status();
  EXPECT_EQ(queued.state, SessionState::queued);
  EXPECT_EQ(queued.samples_done, 300u);
  EXPECT_EQ(queued.samples_target, 800u);
  EXPECT_TRUE(session.cancel());
  EXPECT_EQ(session.status().samples_target, 300u);
  session.request_extend(500);
  std::atomic<bool> stopping{true};
  session.run_job(stopping);  // the daemon stops before a worker starts it
  EXPECT_EQ(session.status().samples_target, 300u);
  EXPECT_EQ(session.status().last_error, "daemon stopped before the job started");
  session.request_extend(500);
  session.run_job(never);
  EXPECT_EQ(session.status().samples_done, 800u);
  EXPECT_EQ(session.status().samples_target, 800u);
}

}  // namespace
}  // namespace ispars::service
