// The records of accepted jobs: written whole, read back, forgotten only by their own job, and
// left alone (not resumed) when unreadable.

#include <gtest/gtest.h>

#include <fstream>

#include "ispars/service/pending_jobs.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

TEST(PendingJobs, ARecordRoundTripsAndIsForgottenOnlyByItsOwnJob) {
  test::TempDir dir;
  BuildRequest build;
  build.method = BuildMethod::spars;
  build.variant = SparsVariant::alg1;
  build.samples = 12345;
  build.seed = 77;
  build.overrides.dense_delta = 1.5;
  build.overrides.stretch = 2.0;
  build.overrides.stretch_slack_after = 20000;
  build.replace = true;
  save_pending_job(dir.path(), PendingJob{"tower", 41, build, 9001, 12345, 2, std::nullopt});
  save_pending_job(dir.path(), PendingJob{"bridge", 42, std::nullopt, 0, 800, 0, std::nullopt});

  auto jobs = pending_jobs(dir.path());
  ASSERT_EQ(jobs.size(), 2u);
  std::sort(jobs.begin(), jobs.end(), [](const auto& a, const auto& b) { return a.scene < b.scene; });
  EXPECT_EQ(jobs[0].scene, "bridge");
  EXPECT_FALSE(jobs[0].build.has_value());
  EXPECT_EQ(jobs[0].target, 800u);
  ASSERT_TRUE(jobs[1].build.has_value());
  EXPECT_EQ(jobs[1].id, 41u);
  EXPECT_EQ(jobs[1].generation, 9001u);
  EXPECT_EQ(jobs[1].attempts, 2u);
  EXPECT_EQ(jobs[1].build->method, BuildMethod::spars);
  EXPECT_EQ(jobs[1].build->variant, SparsVariant::alg1);
  EXPECT_EQ(jobs[1].build->seed, 77u);
  EXPECT_EQ(jobs[1].build->overrides, build.overrides);
  EXPECT_TRUE(jobs[1].build->replace);

  forget_pending_job(dir.path(), "tower", 40);  // an earlier job of the scene: not this record
  EXPECT_EQ(pending_jobs(dir.path()).size(), 2u);
  forget_pending_job(dir.path(), "tower", 41);
  EXPECT_EQ(pending_jobs(dir.path()).size(), 1u);
  forget_pending_job(dir.path(), "bridge");  // whichever job it is
  EXPECT_TRUE(pending_jobs(dir.path()).empty());
}

TEST(PendingJobs, ATasksRecordKeepsItsNameAndEveryPoiExactly) {
  test::TempDir dir;
  InspectionTask task{"welds", {Vec3(0.1, -2.0 / 3.0, 1e-17), Vec3(123456.789, 0, -0.0)}};
  save_pending_job(dir.path(), PendingJob{"tower", 5, std::nullopt, 0, 0, 1, task});
  const auto jobs = pending_jobs(dir.path());
  ASSERT_EQ(jobs.size(), 1u);
  ASSERT_TRUE(jobs[0].task.has_value());
  EXPECT_FALSE(jobs[0].build.has_value());
  EXPECT_EQ(jobs[0].task->name, "welds");
  EXPECT_EQ(jobs[0].task->pois, task.pois) << "doubles written in JSON come back bit for bit";
}

TEST(PendingJobs, AnUnreadableRecordIsLeftAsItIsAndNotResumed) {
  test::TempDir dir;
  save_pending_job(dir.path(), PendingJob{"tower", 1, std::nullopt, 0, 10, 0, std::nullopt});
  std::filesystem::create_directories(dir.path() / ".jobs");
  std::ofstream(dir.path() / ".jobs" / "bridge.json") << "{\"scene\": \"bridge\", \"id\": ";            // torn
  std::ofstream(dir.path() / ".jobs" / "other.json") << R"({"scene": "tower", "id": 2, "target": 5})";  // misnamed
  std::ofstream(dir.path() / ".jobs" / "tower.json.tmp") << "{";  // a write a crash interrupted
  const auto jobs = pending_jobs(dir.path());
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(jobs[0].scene, "tower");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / ".jobs" / "tower.json.tmp"));
  forget_pending_job(dir.path(), "bridge", 7);  // cannot tell whose it is: kept
  EXPECT_TRUE(std::filesystem::exists(dir.path() / ".jobs" / "bridge.json"));
  EXPECT_EQ(test::read_text(dir.path() / ".jobs" / "bridge.json"), "{\"scene\": \"bridge\", \"id\": ");
}

// A record whose seal fails (one digit of its target changed: 2500 -> 3500) is not believed: not
// resumed, and left as it is. A record without a seal (written before seals) is read as before.
TEST(PendingJobs, ARecordThatFailsItsChecksumIsNotResumed) {
  test::TempDir dir;
  save_pending_job(dir.path(), PendingJob{"tower", 1, std::nullopt, 0, 2500, 0, std::nullopt});
  const auto path = dir.path() / ".jobs" / "tower.json";
  std::string text = test::read_text(path);
  ASSERT_NE(text.find("\"crc32\""), std::string::npos) << text;
  const auto at = text.find("2500");
  ASSERT_NE(at, std::string::npos) << text;
  text[at] = '3';
  std::ofstream(path, std::ios::trunc) << text;
  EXPECT_TRUE(pending_jobs(dir.path()).empty()) << "a record that fails its checksum was resumed";
  EXPECT_EQ(test::read_text(path), text);
  std::ofstream(path, std::ios::trunc) << R"({"scene": "tower", "id": 2, "target": 5})";
  ASSERT_EQ(pending_jobs(dir.path()).size(), 1u);
  EXPECT_EQ(pending_jobs(dir.path())[0].target, 5u);
}

}  // namespace
}  // namespace ispars::service
