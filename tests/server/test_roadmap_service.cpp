// The service core without DDS: every operation in typed form, its events, tour admission and
// stopping, and refusals that change nothing.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "server/service_waits.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

using namespace std::chrono_literals;
using test::eventually;

class RoadmapServiceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_.path() / "scenes");
    int seed = 1;
    for (const char* name : {"s0", "s1"}) {
      std::ofstream(dir_.path() / "scenes" / (std::string(name) + ".yaml"))
          << "procedural: {kind: tank_tower, seed: " << seed++ << "}\n";
    }
  }
  ServiceSettings settings(unsigned tour_workers = 1) const {
    ServiceSettings s;
    s.server_id = "unit";
    s.scene_dir = dir_.path() / "scenes";
    s.data_dir = dir_.path() / "data";
    s.build_workers = 1;
    s.tour_workers = tour_workers;
    s.tours_per_worker = 1;
    return s;
  }
  // A stored roadmap of scene s0 at 1,500 samples, its service stopped: the resume tests start there.
  void store_s0() const {
    RoadmapService service(settings(), {});
    service.load("s0");
    service.build("s0", ispars(1500));
    ASSERT_EQ(wait_idle(service, "s0").samples_done, 1500u);
  }
  static BuildRequest ispars(std::uint64_t samples) {
    BuildRequest r;
    r.samples = samples;
    return r;
  }
  // Waits until the scene has no job queued or running.
  static SessionStatus wait_idle(const RoadmapService& service, const std::string& scene) {
    return test::wait_idle(service, scene);
  }
  test::TempDir dir_;
};

TEST_F(RoadmapServiceTest, OperationsRunWithoutDdsAndReportThroughEvents) {
  std::atomic<int> commits{0}, statuses{0}, scene_changes{0};
  std::vector<std::string> unloaded;
  std::mutex unloaded_mutex;
  ServiceEvents events;
  events.on_commit = [&](const std::string& scene, const RoadmapBatch&, std::uint64_t, std::uint64_t, std::size_t) {
    EXPECT_EQ(scene, "s0");
    ++commits;
  };
  events.on_status = [&](const RoadmapSession&) { ++statuses; };
  events.on_scenes_changed = [&] { ++scene_changes; };
  events.on_unloaded = [&](const std::string& scene, bool) {
    std::lock_guard lock(unloaded_mutex);
    unloaded.push_back(scene);
  };
  RoadmapService service(settings(), events);
  const auto listed = service.list_scenes();
  ASSERT_EQ(listed.size(), 2u);
  EXPECT_FALSE(listed[0].loaded);
  EXPECT_TRUE(service.load("s0").second);
  EXPECT_FALSE(service.load("s0").second) << "a second load is not a new session";
  EXPECT_EQ(scene_changes.load(), 1);
  service.build("s0", ispars(1500));
  const SessionStatus built = wait_idle(service, "s0");
  EXPECT_EQ(built.state, SessionState::idle);
  EXPECT_EQ(built.samples_done, 1500u);
  EXPECT_GT(commits.load(), 0);
  EXPECT_GT(statuses.load(), 2);
  service.extend("s0", 500);
  EXPECT_EQ(wait_idle(service, "s0").samples_done, 2000u);
  EXPECT_EQ(service.verify("s0").violations(), 0u);
  EXPECT_TRUE(service.verify("s0").invariant_promised);
  // A snapshot chunk decodes to the published roadmap.
  const SnapshotSlice slice = service.snapshot("s0", 0, 0, 0);
  ASSERT_EQ(slice.chunk_count, 1u);
  Roadmap copy(service.session("s0")->scene().pois().size());
  apply_batch(copy, decode_batch(slice.encoded->substr(slice.begin, slice.end - slice.begin)));
  EXPECT_EQ(roadmap_digest(copy), roadmap_digest(*service.session("s0")->published().roadmap));
  service.unload("s0");
  EXPECT_THROW((void)service.stats("s0"), params::InputError);
  EXPECT_TRUE(service.list_scenes()[0].has_roadmap) << "the store stays on disk";
  EXPECT_EQ(unloaded, std::vector<std::string>{"s0"});
  // A restart's reload skips an unloaded scene; a load brings its stored roadmap back as it was.
  service.load_stored_roadmaps();
  EXPECT_THROW((void)service.stats("s0"), params::InputError);
  EXPECT_TRUE(service.load("s0").second);
  EXPECT_EQ(service.stats("s0").samples_done, 2000u);
}

TEST_F(RoadmapServiceTest, RefusalsNameTheFieldAndChangeNothing) {
  RoadmapService service(settings(), {});
  const auto refused = [&](const auto& call, const std::string& needle) {
    try {
      call();
      ADD_FAILURE() << "not refused: " << needle;
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  refused([&] { (void)service.load("../s0"); }, "request: scene: '../s0' is not a scene name");
  refused([&] { (void)service.stats("s1"); }, "request: scene: scene 's1' is not loaded on daemon unit");
  (void)service.load("s0");
  refused([&] { service.build("s0", ispars(0)); }, "request: samples: must be at least 1");
  refused([&] { service.extend("s0", 0); }, "request: samples: must be at least 1");
  refused([&] { service.extend("s0", 10); }, "has no roadmap to extend");
  TourRequest tour;
  refused([&] { service.start_tour("s0", tour, {}); }, "has no roadmap yet");
  EXPECT_EQ(service.stats("s0").state, SessionState::empty);
  service.build("s0", ispars(800));
  wait_idle(service, "s0");
  tour.budget_seconds = 0.0;
  refused([&] { service.start_tour("s0", tour, {}); }, "request: budget: must be in (0, 3600]");
  tour.budget_seconds = 3601.0;
  refused([&] { service.start_tour("s0", tour, {}); }, "request: budget");
  tour.budget_seconds = 1.0;
  tour.targets.assign(kMaxTourTargets + 1, 0);
  refused([&] { service.start_tour("s0", tour, {}); }, "request: targets: 1000001 given");
  refused([&] { service.build("s0", ispars(10)); }, "request: replace");
  EXPECT_EQ(service.stats("s0").samples_done, 800u);
}

TEST_F(RoadmapServiceTest, BuildsPastTheMemoryBudgetAreRefusedBeforeAnyMemoryGrows) {
  ServiceSettings s = settings();
  s.memory_budget_bytes = 64.0 * 1024 * 1024;
  RoadmapService service(s, {});
  (void)service.load("s0");
  (void)service.load("s1");
  const double rss_before = test::peak_rss_mib();
  const auto refused = [&](const std::string& scene, const BuildRequest& request) {
    try {
      service.build(scene, request);
      ADD_FAILURE() << "accepted a build past the budget";
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("request: samples: the roadmap would hold about"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("more than this daemon's memory budget leaves"), std::string::npos)
          << e.what();
    }
  };
  BuildRequest huge_delta = ispars(3000);
  huge_delta.overrides.dense_delta = 1e6;
  refused("s0", huge_delta);
  refused("s0", ispars(50'000'000));  // huge N
  BuildRequest tiny_delta_huge_n = ispars(40'000'000);
  tiny_delta_huge_n.overrides.dense_delta = 0.1;
  refused("s0", tiny_delta_huge_n);
  EXPECT_LT(test::peak_rss_mib() - rss_before, 16.0) << "a refused build grew memory";
  EXPECT_EQ(service.stats("s0").state, SessionState::empty) << "a refusal changed nothing";
  // What fits is built; the budget then counts it against the other scene.
  service.build("s0", ispars(2000));
  wait_idle(service, "s0");
  // A scene reserves its peak (its roadmap and one compaction fold of it), not its steady state.
  const double held = service.session("s0")->expected_cost().peak_bytes;
  EXPECT_GT(held, service.session("s0")->expected_cost().bytes);
  // The fewest samples whose s1 build does not fit beside s0 (the cost never falls as samples
  // grow): one sample fewer fits beside it, so this one fits alone.
  const auto cost_of = [&](std::uint64_t samples) {
    const auto scene = service.session("s1");
    RoadmapRecipe recipe;
    recipe.dense_delta = scene->scene().config().dense_delta;
    recipe.sparse_delta = scene->scene().config().sparse_delta;
    return planning::estimate_build_cost(scene->scene(), recipe, samples, free_fraction(scene->scene())).peak_bytes;
  };
  std::uint64_t fits_beside = 2000, too_many = 10'000'000;
  ASSERT_LE(cost_of(fits_beside) + held, s.memory_budget_bytes);
  ASSERT_GT(cost_of(too_many) + held, s.memory_budget_bytes);
  while (too_many - fits_beside > 1) {
    const std::uint64_t mid = fits_beside + (too_many - fits_beside) / 2;
    (cost_of(mid) + held > s.memory_budget_bytes ? too_many : fits_beside) = mid;
  }
  refused("s1", ispars(too_many));
  service.unload("s0");  // its share is free again
  service.build("s1", ispars(too_many));
  EXPECT_EQ(wait_idle(service, "s1").state, SessionState::idle);
  // An extend is costed at its total: the roadmap grows into what the budget no longer has.
  try {
    service.extend("s1", 50'000'000);
    ADD_FAILURE() << "an extend past the budget was accepted";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("memory budget"), std::string::npos) << e.what();
  }
}

TEST_F(RoadmapServiceTest, ToursAreAdmittedUpToTheBoundAndCancelAndStopEndThem) {
  RoadmapService service(settings(/*tour_workers=*/1), {});
  (void)service.load("s0");
  service.build("s0", ispars(1500));
  wait_idle(service, "s0");
  std::mutex mutex;
  std::condition_variable changed;
  int done = 0;
  std::vector<double> costs;
  std::atomic<int> progress{0};
  const auto callbacks = [&] {
    TourCallbacks c;
    c.progress = [&](double, double cost, double) { progress += cost > 0.0; };  // reports with a tour
    c.done = [&](TourOutcome outcome) {
      std::lock_guard lock(mutex);
      EXPECT_TRUE(outcome.result.validation.valid());
      EXPECT_EQ(outcome.waypoints.size(), outcome.result.tour.walk.size());
      costs.push_back(outcome.result.tour.cost);
      ++done;
      changed.notify_all();
    };
    c.failed = [&](const std::string& error) { ADD_FAILURE() << error; };
    return c;
  };
  TourRequest tour;
  tour.budget_seconds = 600.0;
  service.start_tour("s0", tour, callbacks());  // one worker, one admitted per worker
  try {
    service.start_tour("s0", tour, callbacks());
    ADD_FAILURE() << "a second tour was admitted past the bound";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("busy: 1 tours are queued or running"), std::string::npos) << e.what();
  }
  // Cancelled once it has a tour (its first progress report), so that it ends with its best: a
  // tour cancelled before its first one fails instead, which a loaded machine can make happen
  // after any fixed wait.
  const auto until_progress = [&](int above) {
    return eventually([&] { return progress.load() > above; }, 30s, "the tour reports progress", 10ms);
  };
  ASSERT_TRUE(until_progress(0));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(service.cancel("s0").tours_stopped, 1u);
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(changed.wait_for(lock, 30s, [&] { return done == 1; })) << "cancel did not end the tour";
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  EXPECT_GT(progress.load(), 0);
  // The slot is free again once the tour has returned; stop() ends a running tour with its best.
  ASSERT_TRUE(eventually(
      [&] {
        try {
          service.start_tour("s0", tour, callbacks());
          return true;
        } catch (const params::InputError&) {
          return false;
        }
      },
      2s, "the finished tour's slot is released", 10ms));
  const int first_progress = progress.load();
  ASSERT_TRUE(until_progress(first_progress)) << "the second tour reported no progress within 30 s";
  service.stop();
  std::lock_guard lock(mutex);
  EXPECT_EQ(done, 2);
  ASSERT_EQ(costs.size(), 2u);
  EXPECT_GT(costs[1], 0.0);
}

}  // namespace
}  // namespace ispars::service

namespace ispars::service {
namespace {

TEST_F(RoadmapServiceTest, AYieldedSceneStopsItsBuildsAndLeavesWithoutAnUnloadedMark) {
  std::mutex mutex;
  std::vector<std::pair<std::string, bool>> unloaded;
  std::vector<std::string> claimed, released;
  ServiceEvents events;
  events.claim = [&](const std::string& s) {
    std::lock_guard lock(mutex);
    claimed.push_back(s);
  };
  events.release = [&](const std::string& s) {
    std::lock_guard lock(mutex);
    released.push_back(s);
  };
  events.on_unloaded = [&](const std::string& s, bool given_up) {
    std::lock_guard lock(mutex);
    unloaded.emplace_back(s, given_up);
  };
  auto s = settings();
  s.memory_budget_bytes = 1e18;
  RoadmapService service(s, events);
  (void)service.load("s0");
  (void)service.load("s1");
  service.build("s0", ispars(2'000));
  wait_idle(service, "s0");
  service.build("s1", ispars(50'000'000));  // runs on the only build worker
  ASSERT_TRUE(eventually([&] { return service.stats("s1").samples_done > 0; }, 30s, "s1 runs, with a commit", 10ms));
  service.extend("s0", 1'000);  // queued behind it: cancelled at once by the yield
  const std::atomic<bool> give_up{false};
  const auto t0 = std::chrono::steady_clock::now();
  service.yield("s0", give_up);
  service.yield("s1", give_up);  // the running build stops after its current chunk
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 5s);
  EXPECT_TRUE(service.loaded_scenes().empty());
  {
    std::lock_guard lock(mutex);
    EXPECT_EQ(unloaded, (std::vector<std::pair<std::string, bool>>{{"s0", true}, {"s1", true}}));
    EXPECT_EQ(released, claimed);
  }
  // Not marked unloaded: a restart reloads the stored roadmap; a yield of an unloaded scene is a no-op.
  EXPECT_FALSE(marked_unloaded(dir_.path() / "data" / "s0"));
  service.yield("s0", give_up);
  EXPECT_EQ(list_stored_roadmaps(dir_.path() / "data", service.loaded_scenes()).scenes,
            (std::vector<std::string>{"s0", "s1"}));
}

// A takeover is a writer too: four readers looping VERIFY do not hold up giving the scene to
// its owner (before, the fleet thread spun in yield() for as long as verifies overlapped).
TEST_F(RoadmapServiceTest, AYieldIsNotHeldUpByLoopingVerifies) {
  auto s = settings();
  s.memory_budget_bytes = 1e18;
  RoadmapService service(s, {});
  (void)service.load("s0");
  service.build("s0", ispars(30'000));
  wait_idle(service, "s0");
  std::atomic<bool> done{false};
  std::atomic<int> verified{0}, stopped{0};
  std::atomic<std::chrono::steady_clock::time_point> yield_at{std::chrono::steady_clock::time_point::max()};
  std::atomic<std::chrono::steady_clock::duration> worst_lag{std::chrono::steady_clock::duration::zero()};
  std::vector<std::jthread> readers;
  struct StopReaders {
    std::atomic<bool>& done;
    ~StopReaders() { done = true; }
  } stop_readers{done};
  for (int i = 0; i < 4; ++i) {
    readers.emplace_back([&] {
      while (!done) {
        try {
          (void)service.verify("s0");
          ++verified;
        } catch (const std::exception& e) {
          if (std::string(e.what()).find("was stopped: scene 's0' is being given up to its owner") !=
              std::string::npos) {
            ++stopped;
            const auto lag = std::chrono::steady_clock::now() - yield_at.load();
            for (auto worst = worst_lag.load(); lag > worst && !worst_lag.compare_exchange_weak(worst, lag);) {
            }
          }
          std::this_thread::sleep_for(1ms);
        }
      }
    });
  }
  // Up to 2 min: a verify of 30,000 samples takes tens of seconds under the sanitizers.
  ASSERT_TRUE(eventually([&] { return verified >= 4; }, 120s, "four verifies done", 10ms));
  const std::atomic<bool> give_up{false};
  yield_at = std::chrono::steady_clock::now();
  service.yield("s0", give_up);
  // The verifies stop within half a second; the yield's own work (closing the store) is bounded
  // loosely, as a loaded machine takes its time over that.
  EXPECT_LT(std::chrono::steady_clock::now() - yield_at.load(), 5s) << "the takeover waited for the verifies";
  EXPECT_TRUE(service.loaded_scenes().empty());
  done = true;
  readers.clear();
  EXPECT_GT(stopped, 0) << "no verify was running when the scene was given up";
  EXPECT_LT(worst_lag.load(), 500ms) << "a verify ran on after the scene was being given up";
}

}  // namespace
}  // namespace ispars::service

namespace ispars::service {
namespace {

// A recorded job is resumed at the next start, with its attempt counted; one resumed three times
// already (each time the daemon stopped or died under it) is given up and forgotten, and the
// roadmap stays at its last commit.
TEST_F(RoadmapServiceTest, AJobIsResumedWithItsAttemptCountedAndGivenUpAfterThree) {
  store_s0();
  const auto data = dir_.path() / "data";
  save_pending_job(data, PendingJob{"s0", 7, std::nullopt, 0, 2500, 3, std::nullopt});
  {
    RoadmapService service(settings(), {});
    service.load_stored_roadmaps();
    service.resume_pending_jobs();
    EXPECT_EQ(wait_idle(service, "s0").samples_done, 1500u) << "a job resumed three times was resumed again";
    EXPECT_TRUE(pending_jobs(data).empty()) << "a job given up stays recorded";
  }
  save_pending_job(data, PendingJob{"s0", 8, std::nullopt, 0, 2500, 2, std::nullopt});
  {
    RoadmapService service(settings(), {});
    service.load_stored_roadmaps();
    service.resume_pending_jobs();
    const auto jobs = pending_jobs(data);  // recorded anew before it runs, with the attempt counted
    if (!jobs.empty()) {
      EXPECT_EQ(jobs[0].attempts, 3u);
    }
    EXPECT_EQ(wait_idle(service, "s0").samples_done, 2500u);
    // The worker forgets the record just after the session turns idle, not in the same step.
    EXPECT_TRUE(
        eventually([&] { return pending_jobs(data).empty(); }, 5s, "a finished job's record is forgotten", 10ms));
  }
}

// Clean stops (SIGTERM, a rolling upgrade) do not count against the resume cap: a job the daemon
// died under twice, then stopped cleanly under, is stopped cleanly four times more, and each start
// resumes it, its attempts still 2; a death counts again, and the next one ends it.
TEST_F(RoadmapServiceTest, CleanStopsDoNotCountAgainstTheResumeCap) {
  store_s0();
  const auto data = dir_.path() / "data";
  save_pending_job(data, PendingJob{"s0", 7, std::nullopt, 0, 400'000, 2, std::nullopt, /*stopped_cleanly=*/true});
  for (int stop = 0; stop < 4; ++stop) {
    {
      RoadmapService service(settings(), {});
      service.load_stored_roadmaps();
      service.resume_pending_jobs();
      ASSERT_EQ(pending_jobs(data).size(), 1u) << "stop " << stop << ": the job was not resumed";
    }  // a clean stop, with the job running or queued
    const auto jobs = pending_jobs(data);
    ASSERT_EQ(jobs.size(), 1u) << "stop " << stop << ": a cleanly stopped job was forgotten";
    EXPECT_EQ(jobs[0].attempts, 2u) << "stop " << stop << ": a clean stop was counted";
    EXPECT_TRUE(jobs[0].stopped_cleanly);
    EXPECT_EQ(jobs[0].target, 400'000u);
  }
  // The daemon dies under it (its record as the resume wrote it: not stopped cleanly).
  PendingJob died = pending_jobs(data)[0];
  died.stopped_cleanly = false;
  save_pending_job(data, died);
  {
    RoadmapService service(settings(), {});
    service.load_stored_roadmaps();
    service.resume_pending_jobs();
    const auto jobs = pending_jobs(data);
    ASSERT_EQ(jobs.size(), 1u);
    EXPECT_EQ(jobs[0].attempts, 3u) << "a death was not counted";
    EXPECT_FALSE(jobs[0].stopped_cleanly);
  }
  died = pending_jobs(data)[0];  // and dies under it once more
  died.stopped_cleanly = false;
  save_pending_job(data, died);
  {
    RoadmapService service(settings(), {});
    service.load_stored_roadmaps();
    service.resume_pending_jobs();
    EXPECT_TRUE(pending_jobs(data).empty()) << "a job the daemon died under three times was resumed again";
  }
}

// Once the daemon stops its readers, a snapshot encoding is refused by name at its next slice
// (before, an encoding ran to its end, and a large one could outlast the stop watchdog).
TEST_F(RoadmapServiceTest, ASnapshotEncodingStopsWhenTheReadersAreStopped) {
  RoadmapService service(settings(), {});
  (void)service.load("s0");
  service.build("s0", ispars(500));
  wait_idle(service, "s0");
  EXPECT_GT(service.snapshot("s0", 0, 0, 0, 0).encoded->size(), 0u);
  service.stop_all_readers("the daemon is stopping");
  try {
    (void)service.snapshot("s0", 0, 0, 0, 0);
    ADD_FAILURE() << "a snapshot was encoded after the stop";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the snapshot of scene 's0' was stopped: the daemon is stopping"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ispars::service
