// A session's writers (roadmap_session_writers.cpp) and the tasks they keep: a task's addition as
// a job, what verify finds after it, recovery of the task from the store, a task's removal, the
// requests refused; and the drop, remembered after its store is gone (the fleet weighs the
// drop's empty roadmap) and refused whole when it cannot be remembered.

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <fstream>
#include <future>
#include <mutex>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "roadmap_session_fixture.hpp"

namespace ispars::service {
namespace {

InspectionTask sampled_task(const std::string& name, std::size_t count, std::uint64_t seed) {
  return {name, sample_task_pois(test::shared_scene("demo_tank_tower"), count, seed)};
}

std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "(not refused)";
}

// The disk, with file syncs that wait while held (a slow fsync, on demand).
class HeldSyncs final : public FileSystem {
 public:
  void hold() {
    std::lock_guard lock(mutex_);
    held_ = true;
    entered_ = false;
  }
  void release() {
    std::lock_guard lock(mutex_);
    held_ = false;
    changed_.notify_all();
  }
  // Whether a sync started waiting within `timeout`.
  bool wait_entered(std::chrono::seconds timeout) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return entered_; });
  }
  std::unique_ptr<File> open(const std::filesystem::path& path, Open how) override {
    auto inner = disk().open(path, how);
    return inner ? std::make_unique<HeldFile>(std::move(inner), *this) : nullptr;
  }
  std::optional<std::string> read(const std::filesystem::path& p) const override { return disk().read(p); }
  bool exists(const std::filesystem::path& p) const override { return disk().exists(p); }
  std::optional<std::uint64_t> file_size(const std::filesystem::path& p) const override { return disk().file_size(p); }
  std::vector<std::string> list(const std::filesystem::path& d) const override { return disk().list(d); }
  void rename(const std::filesystem::path& a, const std::filesystem::path& b) override { disk().rename(a, b); }
  bool exchange(const std::filesystem::path& a, const std::filesystem::path& b) override {
    return disk().exchange(a, b);
  }
  bool remove(const std::filesystem::path& p) override { return disk().remove(p); }
  void remove_all(const std::filesystem::path& p) override { disk().remove_all(p); }
  bool create_directories(const std::filesystem::path& d) override { return disk().create_directories(d); }
  void sync_directory(const std::filesystem::path& d) override { disk().sync_directory(d); }
  std::unique_ptr<Lock> lock(const std::filesystem::path& d) override { return disk().lock(d); }

 private:
  class HeldFile final : public File {
   public:
    HeldFile(std::unique_ptr<File> inner, HeldSyncs& fs) : inner_(std::move(inner)), fs_(fs) {}
    void append(std::string_view bytes) override { inner_->append(bytes); }
    void truncate(std::uint64_t size) override { inner_->truncate(size); }
    void sync() override {
      {
        std::unique_lock lock(fs_.mutex_);
        fs_.entered_ = fs_.entered_ || fs_.held_;
        fs_.changed_.notify_all();
        fs_.changed_.wait(lock, [&] { return !fs_.held_; });
      }
      inner_->sync();
    }
    std::uint64_t size() const override { return inner_->size(); }
    std::string read(std::uint64_t offset, std::size_t count) const override { return inner_->read(offset, count); }

   private:
    std::unique_ptr<File> inner_;
    HeldSyncs& fs_;
  };
  std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false;
  bool entered_ = false;
};

// A removal commits durably before it answers; while its fsync waits, the scene's status (what
// STATS and every status message read) is answered. Before, the commit ran under the session's
// mutex, and a slow disk held up every status read.
TEST(SessionTaskRemoval, TheStatusIsReadWhileARemovalWaitsOnTheDisk) {
  HeldSyncs fs;
  test::TempDir dir;
  std::atomic<bool> never{false};
  RoadmapSession session("tower", test::shared_scene("demo_tank_tower"), dir.path() / "tower", SessionLimits{}, {}, fs);
  BuildRequest request;
  request.samples = 300;
  request.seed = 4;
  session.request_build(request);
  session.run_job(never);
  session.request_task(sampled_task("a", 10, 1));
  session.run_job(never);
  ASSERT_EQ(session.status().tasks, 1u);
  fs.hold();
  std::thread removal([&] { EXPECT_EQ(session.remove_task("a"), 0u); });
  const bool waiting = fs.wait_entered(std::chrono::seconds(10));
  auto status = std::async(std::launch::async, [&] { return session.status(); });
  const bool answered = status.wait_for(std::chrono::seconds(5)) == std::future_status::ready;
  fs.release();
  removal.join();
  ASSERT_TRUE(waiting) << "the removal never synced";
  EXPECT_TRUE(answered) << "the status waited on the removal's fsync";
  EXPECT_EQ(status.get().tasks, 1u) << "read before the removal was durable";
  EXPECT_EQ(session.status().tasks, 0u);
}

class SessionTaskTest : public RoadmapSessionTest, public ::testing::WithParamInterface<BuildMethod> {
 protected:
  BuildRequest request(std::uint64_t samples) const {
    BuildRequest r = ispars(samples, 4);
    r.method = GetParam();
    return r;
  }
  // The same build and the same task in-process, without the service: the roadmap a session
  // must hold byte for byte.
  std::unique_ptr<planning::RoadmapBuilder> reference(std::uint64_t samples, const std::vector<InspectionTask>& tasks,
                                                      std::vector<std::unique_ptr<planning::Scene>>& scenes) const {
    planning::BuildOptions options;
    options.seed = 4;
    scenes.push_back(std::make_unique<planning::Scene>(scene()));
    auto b = planning::make_roadmap_builder(GetParam(), *scenes.back(), options);
    b->extend(samples);
    for (const InspectionTask& t : tasks) {
      scenes.push_back(std::make_unique<planning::Scene>(scenes.back()->with_more_pois(t.pois)));
      b->add_pois(*scenes.back());
    }
    return b;
  }
};

TEST_P(SessionTaskTest, ATaskKeepsInvariantOneOverEveryPoiAndARestartRecoversItByteForByte) {
  const InspectionTask task = sampled_task("welds", 60, 11);
  std::uint64_t live = 0;
  {
    auto session = open();
    session->request_build(request(5000));
    session->run_job(never_);
    const std::size_t base_pois = session->status().poi_count;
    EXPECT_EQ(session->request_task(task), 1u);
    EXPECT_EQ(session->status().state, SessionState::queued);
    session->run_job(never_);
    const SessionStatus s = session->status();
    ASSERT_EQ(s.state, SessionState::idle) << s.last_error;
    EXPECT_EQ(s.tasks, 1u);
    EXPECT_EQ(s.poi_count, base_pois + task.pois.size());
    EXPECT_EQ(s.samples_done, 5000u) << "a task draws no samples";
    const planning::VerificationReport report = session->verify(kVerifyBudget);
    EXPECT_TRUE(report.geometry_ok());
    EXPECT_EQ(report.invariant_violations, 0u) << "Invariant 1 over the scene's and the task's POIs";
    live = roadmap_digest(*session->published().roadmap);
    std::vector<std::unique_ptr<planning::Scene>> scenes;
    EXPECT_EQ(live, roadmap_digest(reference(5000, {task}, scenes)->roadmap()))
        << "the session's roadmap is the builder's with the task, byte for byte";
  }
  // A restart: the store holds the task's commit; the vertices built before it see its POIs again.
  auto session = open();
  EXPECT_EQ(session->status().tasks, 1u);
  ASSERT_EQ(session->tasks().size(), 1u);
  EXPECT_EQ(session->tasks()[0].name, "welds");
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), live) << session->recovery_note();
  EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
  // Later samples treat the task's POIs as the scene's: the extended roadmap is the reference's.
  session->request_extend(1500);
  session->run_job(never_);
  std::vector<std::unique_ptr<planning::Scene>> scenes;
  auto b = reference(5000, {task}, scenes);
  b->extend(1500);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), roadmap_digest(b->roadmap()));
  EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
}

TEST_P(SessionTaskTest, ARebuildKeepsTheTasksAndADropForgetsThem) {
  auto session = open();
  session->request_build(request(3000));
  session->run_job(never_);
  session->request_task(sampled_task("a", 30, 1));
  session->run_job(never_);
  BuildRequest again = request(3000);
  again.replace = true;
  again.seed = 9;
  session->request_build(again);
  session->run_job(never_);
  EXPECT_EQ(session->status().tasks, 1u) << "a replacing build is built with the tasks' POIs";
  EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
  const std::uint64_t rebuilt = roadmap_digest(*session->published().roadmap);
  session.reset();
  session = open();
  EXPECT_EQ(session->status().tasks, 1u);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), rebuilt);
  session->drop();
  EXPECT_EQ(session->status().tasks, 0u);
  EXPECT_EQ(session->status().poi_count, scene().pois().size());
}

TEST_P(SessionTaskTest, ARemovalChangesNoVertexIsDurableAndFreesTheName) {
  const InspectionTask a = sampled_task("a", 30, 1), b = sampled_task("b", 20, 2), again = sampled_task("a", 25, 3);
  std::uint64_t digest = 0;
  {
    auto session = open();
    session->request_build(request(3000));
    session->run_job(never_);
    for (const InspectionTask& t : {a, b}) {
      session->request_task(t);
      session->run_job(never_);
    }
    digest = roadmap_digest(*session->published().roadmap);
    const std::size_t pois = session->status().poi_count;
    EXPECT_EQ(session->remove_task("a"), 1u);
    EXPECT_EQ(session->status().tasks, 1u);
    EXPECT_EQ(session->status().poi_count, pois) << "a removed task's POIs keep their ids";
    EXPECT_EQ(roadmap_digest(*session->published().roadmap), digest) << "a removal changes no vertex or edge";
    ASSERT_EQ(session->tasks().size(), 2u);
    EXPECT_TRUE(session->tasks()[0].removed);
    EXPECT_NE(refusal([&] { session->remove_task("a"); }).find("task 'a' was removed already"), std::string::npos);
    EXPECT_NE(refusal([&] { session->remove_task("zz"); }).find("no task 'zz'"), std::string::npos);
    session->request_task(again);  // the name is free again
    EXPECT_NE(refusal([&] {
                session->remove_task("b");
              }).find("a build is running on scene 'tower'; remove the task when it is idle"),
              std::string::npos)
        << "refused while an addition is queued";
    session->run_job(never_);
    EXPECT_EQ(session->status().tasks, 2u);
    digest = roadmap_digest(*session->published().roadmap);
  }
  // A restart recovers the removal (the store's commit, acknowledged when remove_task returned).
  auto session = open();
  ASSERT_EQ(session->tasks().size(), 3u);
  EXPECT_TRUE(session->tasks()[0].removed);
  EXPECT_FALSE(session->tasks()[1].removed);
  EXPECT_FALSE(session->tasks()[2].removed);
  EXPECT_EQ(session->status().tasks, 2u);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), digest) << session->recovery_note();
  EXPECT_EQ(session->verify(kVerifyBudget).invariant_violations, 0u);
  // Later samples: the same roadmap as every addition made in-process (a removal changes none).
  session->request_extend(1000);
  session->run_job(never_);
  std::vector<std::unique_ptr<planning::Scene>> scenes;
  auto reference_builder = reference(3000, {a, b, again}, scenes);
  reference_builder->extend(1000);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), roadmap_digest(reference_builder->roadmap()));
  // A replacing build keeps the removal too, across a restart.
  BuildRequest rebuild = request(2000);
  rebuild.replace = true;
  session->request_build(rebuild);
  session->run_job(never_);
  session.reset();
  session = open();
  ASSERT_EQ(session->tasks().size(), 3u);
  EXPECT_TRUE(session->tasks()[0].removed);
  EXPECT_EQ(session->status().tasks, 2u);
}

INSTANTIATE_TEST_SUITE_P(Methods, SessionTaskTest, ::testing::Values(BuildMethod::ispars, BuildMethod::ispars2),
                         [](const auto& param_info) { return std::string(to_string(param_info.param)); });

TEST_F(RoadmapSessionTest, AnAdditionStoppedPartWayLeavesTheRoadmapAsCommitted) {
  std::atomic<bool> stopping{false};
  SessionCallbacks callbacks;
  bool adding = false;
  callbacks.on_status = [&](const SessionStatus& s) {
    // The daemon stops as the addition starts (its first keep_going check sees it).
    if (adding && s.state == SessionState::building) stopping = true;
  };
  auto session = open(callbacks);
  session->request_build(ispars(4000));
  session->run_job(never_);
  const std::uint64_t before = roadmap_digest(*session->published().roadmap);
  adding = true;
  session->request_task(sampled_task("late", 40, 3));
  session->run_job(stopping);
  const SessionStatus s = session->status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_NE(s.last_error.find("task 'late' not added"), std::string::npos) << s.last_error;
  EXPECT_EQ(s.tasks, 0u);
  EXPECT_EQ(s.poi_count, scene().pois().size());
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), before);
  // Asked again, it is added.
  adding = false;
  session->request_task(sampled_task("late", 40, 3));
  session->run_job(never_);
  EXPECT_EQ(session->status().tasks, 1u);
  session.reset();
  EXPECT_EQ(open()->status().tasks, 1u);
}

TEST_F(RoadmapSessionTest, BadTasksAreRefusedByNameAndChangeNothing) {
  auto session = open();
  EXPECT_NE(refusal([&] { session->request_task(sampled_task("t", 5, 1)); }).find("has no roadmap"), std::string::npos);
  session->request_build(ispars(3000));
  EXPECT_NE(refusal([&] { session->request_task(sampled_task("t", 5, 1)); }).find("a build is already running"),
            std::string::npos);
  session->run_job(never_);
  session->request_task(sampled_task("t", 5, 1));
  session->run_job(never_);
  const std::uint64_t digest = roadmap_digest(*session->published().roadmap);
  const std::uint64_t version = session->status().version;
  EXPECT_NE(refusal([&] { session->request_task(sampled_task("t", 5, 2)); }).find("task.name: a task 't' exists"),
            std::string::npos);
  EXPECT_NE(refusal([&] { session->request_task(sampled_task("../x", 5, 2)); }).find("task.name"), std::string::npos);
  EXPECT_NE(refusal([&] {
              session->request_task({"empty", {}});
            }).find("task.pois: a task has at least one POI"),
            std::string::npos);
  InspectionTask far = sampled_task("far", 5, 2);
  far.pois[3] += Vec3(0, 0, 0.5);
  EXPECT_NE(refusal([&] { session->request_task(far); }).find("task.pois[3]"), std::string::npos);
  InspectionTask outside = sampled_task("outside", 5, 2);
  outside.pois[0] = Vec3(1e6, 0, 0);
  EXPECT_NE(refusal([&] { session->request_task(outside); }).find("outside the structure's box"), std::string::npos);
  InspectionTask nan = sampled_task("nan", 5, 2);
  nan.pois[1].x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(refusal([&] { session->request_task(nan); }).find("task.pois[1]: is not a finite point"),
            std::string::npos);
  const SessionStatus s = session->status();
  EXPECT_EQ(s.state, SessionState::idle);
  EXPECT_EQ(s.tasks, 1u);
  EXPECT_EQ(s.version, version);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), digest);
}

TEST_F(RoadmapSessionTest, ADenseRoadmapRefusesATaskNamingTheMethodsThatTakeOne) {
  auto session = open();
  BuildRequest r = ispars(2000);
  r.method = BuildMethod::dense;
  session->request_build(r);
  session->run_job(never_);
  const std::string why = refusal([&] { session->request_task(sampled_task("t", 5, 1)); });
  EXPECT_NE(why.find("cannot take a task without a rebuild (spars, ispars and ispars2 can)"), std::string::npos) << why;
  EXPECT_EQ(session->status().tasks, 0u);
}

TEST_F(RoadmapSessionTest, ADropIsRememberedAcrossAReopenAndALaterBuildIsNewerStill) {
  std::uint64_t built = 0, dropped = 0;
  {
    auto session = open();
    session->request_build(ispars(500));
    session->run_job(never_);
    built = session->status().generation;
    ASSERT_GT(built, 0u);
    session->drop();
    const SessionStatus after = session->status();
    EXPECT_EQ(after.state, SessionState::empty);
    dropped = after.generation;
    EXPECT_GT(dropped, built);
    EXPECT_EQ(session->published().generation, dropped);
    session->close();
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "tower")) << "the store outlived its drop";
  auto session = open();
  EXPECT_EQ(session->status().state, SessionState::empty);
  EXPECT_FALSE(session->status().recipe);
  EXPECT_EQ(session->status().generation, dropped) << "the reopened scene forgot its drop";
  EXPECT_EQ(session->published().generation, dropped);
  session->request_build(ispars(300));
  session->run_job(never_);
  EXPECT_GT(session->status().recipe->generation, dropped);
}

// The mark cannot be written (a file stands where its directory goes): the drop is refused
// naming the file, and the roadmap stays as it was, stored and served.
TEST_F(RoadmapSessionTest, ADropThatCannotBeRememberedIsRefusedAndChangesNothing) {
  auto session = open();
  session->request_build(ispars(500));
  session->run_job(never_);
  const SessionStatus before = session->status();
  const std::uint64_t digest = roadmap_digest(*session->published().roadmap);
  std::ofstream(dir_.path() / ".drops") << "in the way\n";
  try {
    session->drop();
    ADD_FAILURE() << "the drop was not refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(".drops"), std::string::npos) << e.what();
  }
  const SessionStatus after = session->status();
  EXPECT_EQ(after.state, SessionState::idle);
  EXPECT_EQ(after.generation, before.generation);
  EXPECT_EQ(after.samples_done, before.samples_done);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), digest);
  session->request_extend(200);  // the store still takes commits
  session->run_job(never_);
  EXPECT_EQ(session->status().samples_done, before.samples_done + 200);
  session->close();
  auto reopened = open();
  EXPECT_EQ(reopened->status().samples_done, before.samples_done + 200);
  EXPECT_EQ(reopened->status().generation, before.generation);
}

}  // namespace
}  // namespace ispars::service
