// The job queue: a job's record is written as it is accepted and removed when it ends; a job the
// stop interrupts keeps its record (marked stopped cleanly); a refused request records nothing.

#include "ispars/service/job_queue.hpp"

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "server/service_waits.hpp"
#include "server/unit_service.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

using namespace std::chrono_literals;
using test::eventually;

class JobQueueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    service_ = test::service_with_s0(dir_.path(), 0);
    session_ = service_->session("s0");
  }
  static BuildRequest build(std::uint64_t samples) {
    BuildRequest r;
    r.samples = samples;
    return r;
  }
  std::vector<PendingJob> records() const { return pending_jobs(jobs_dir()); }
  std::filesystem::path jobs_dir() const { return dir_.path() / "queue"; }
  bool idle() const { return !session_->busy(); }

  test::TempDir dir_;
  std::unique_ptr<RoadmapService> service_;
  std::shared_ptr<RoadmapSession> session_;
  std::atomic<bool> stopping_{false};
};

TEST_F(JobQueueTest, AJobsRecordGoesWhenItEnds) {
  std::filesystem::create_directories(jobs_dir());
  JobQueue queue(1, jobs_dir(), disk(), stopping_);
  queue.accept(session_, "s0", build(800), 800, 0);
  ASSERT_TRUE(eventually([&] { return idle() && records().empty(); }, 60s, "the job ends and is forgotten"));
  EXPECT_EQ(session_->status().samples_done, 800u);
}

TEST_F(JobQueueTest, AJobTheStopInterruptsKeepsItsRecordMarkedStoppedCleanly) {
  std::filesystem::create_directories(jobs_dir());
  stopping_ = true;  // the daemon stops as the job starts: it returns early, to be resumed
  JobQueue queue(1, jobs_dir(), disk(), stopping_);
  queue.accept(session_, "s0", build(5000), 5000, 2);
  ASSERT_TRUE(eventually([&] { return idle(); }, 60s, "the job returns"));
  queue.stop_workers();
  std::vector<PendingJob> left = records();
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].scene, "s0");
  EXPECT_EQ(left[0].target, 5000u);
  EXPECT_EQ(left[0].attempts, 2u);
  EXPECT_FALSE(left[0].stopped_cleanly);
  queue.mark_stopped_cleanly();
  left = records();
  ASSERT_EQ(left.size(), 1u);
  EXPECT_TRUE(left[0].stopped_cleanly);
  queue.forget("s0", left[0].id + 1);  // another job's id: the record stays
  EXPECT_EQ(records().size(), 1u);
  queue.forget("s0", 0);
  EXPECT_TRUE(records().empty());
}

TEST_F(JobQueueTest, ARefusedRequestRecordsNothing) {
  std::filesystem::create_directories(jobs_dir());
  JobQueue queue(1, jobs_dir(), disk(), stopping_);
  try {
    queue.accept(session_, "s0", std::nullopt, 100, 0);  // an extend with no roadmap to extend
    ADD_FAILURE() << "an extend without a roadmap was accepted";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("request:"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(records().empty());
  EXPECT_TRUE(idle());
}

}  // namespace
}  // namespace ispars::service
