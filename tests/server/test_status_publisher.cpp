// The status publisher without DDS: statuses stamped in order, UNLOADED only when not given up,
// updates kept at a stop, and a new participant's version mark.

#include "ispars/server/status_publisher.hpp"

#include <gtest/gtest.h>

#include "server/recording_outbox.hpp"
#include "server/service_waits.hpp"
#include "server/unit_service.hpp"
#include "support/test_support.hpp"

namespace ispars::server {
namespace {

class StatusPublisherTest : public ::testing::Test {
 protected:
  void SetUp() override { service_ = test::service_with_s0(dir_.path(), 0); }
  void build(std::uint64_t samples) {
    BuildRequest r;
    r.samples = samples;
    service_->build("s0", r);
    (void)test::wait_idle(*service_, "s0");
  }
  test::TempDir dir_;
  test::RecordingOutbox out_;
  DaemonMetrics metrics_;
  std::atomic<bool> leaving_{false};
  std::unique_ptr<service::RoadmapService> service_;
};

TEST_F(StatusPublisherTest, EveryStatusIsStampedAfterTheOneBefore) {
  StatusPublisher publisher("d1", out_, metrics_, leaving_);
  const auto session = service_->session("s0");
  const msg::SceneStatus first = publisher.status_message(*session);
  publisher.publish_status(*session);
  publisher.publish_unloaded("s1", false);
  const msg::SceneStatus last = publisher.status_message(*session);
  const std::vector<msg::SceneStatus> sent = out_.statuses();
  ASSERT_EQ(sent.size(), 2u);
  EXPECT_EQ(first.server_id(), "d1");
  EXPECT_EQ(sent[0].scene(), "s0");
  EXPECT_LT(first.status_seq(), sent[0].status_seq());
  EXPECT_LT(sent[0].status_seq(), sent[1].status_seq());
  EXPECT_LT(sent[1].status_seq(), last.status_seq());
  EXPECT_EQ(sent[1].scene(), "s1");
  EXPECT_EQ(sent[1].state(), msg::SCENE_UNLOADED);
}

TEST_F(StatusPublisherTest, AGivenUpSceneHasNoUnloadedStatusAndAStoppingDaemonRetiresNothing) {
  StatusPublisher publisher("d1", out_, metrics_, leaving_);
  publisher.publish_unloaded("s0", true);  // handed to another daemon: its statuses are the scene's
  EXPECT_TRUE(out_.statuses().empty());
  EXPECT_EQ(out_.retired(), std::vector<std::string>{"s0"});
  leaving_ = true;  // the writer goes with its participant
  publisher.publish_unloaded("s0", false);
  EXPECT_EQ(out_.retired().size(), 1u);
  ASSERT_EQ(out_.statuses().size(), 1u);
  EXPECT_EQ(out_.statuses()[0].state(), msg::SCENE_UNLOADED);
}

TEST_F(StatusPublisherTest, ANewParticipantMarksEachRoadmapsVersion) {
  StatusPublisher publisher("d1", out_, metrics_, leaving_);
  publisher.republish("s0", *service_->session("s0"));  // no roadmap yet: its status alone
  EXPECT_EQ(out_.statuses().size(), 1u);
  EXPECT_TRUE(out_.updates().empty());
  build(300);
  const service::SessionStatus status = service_->stats("s0");
  publisher.republish("s0", *service_->session("s0"));
  ASSERT_EQ(out_.statuses().size(), 2u);
  ASSERT_EQ(out_.updates().size(), 1u);
  const msg::UpdateBatch mark = out_.updates()[0];
  EXPECT_EQ(mark.scene(), "s0");
  EXPECT_EQ(mark.server_id(), "d1");
  EXPECT_EQ(mark.from_version(), status.version);
  EXPECT_EQ(mark.to_version(), status.version);
  EXPECT_EQ(mark.samples_done(), 300u);
  EXPECT_EQ(mark.first_edge(), status.edges);
  EXPECT_TRUE(mark.vertices().empty());
}

TEST_F(StatusPublisherTest, TasksFollowTheirScenesStatus) {
  StatusPublisher publisher("d1", out_, metrics_, leaving_);
  build(300);
  const auto session = service_->session("s0");
  const Vec3 poi = session->scene().pois().front();
  service_->add_task("s0", service::InspectionTask{"seam", {poi}});
  (void)test::wait_idle(*service_, "s0");
  publisher.publish_status(*session);
  const std::vector<msg::SceneTask> tasks = out_.tasks();
  ASSERT_EQ(tasks.size(), 1u);
  EXPECT_EQ(tasks[0].name(), "seam");
  EXPECT_EQ(tasks[0].server_id(), "d1");
  EXPECT_EQ(tasks[0].pois().size(), 1u);
}

}  // namespace
}  // namespace ispars::server
