// The DDS link over real Fast DDS (localhost, a domain of this process's own): nothing runs on a
// closed link, standing still past the lease makes a new participant that announces the daemon
// and republishes its scenes, and a stop ends a rejoin's overlap at once.

#include "ispars/server/dds_link.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "ispars/local/local_daemon.hpp"
#include "ispars/server/daemon_inbox.hpp"
#include "ispars/server/dds_endpoints.hpp"
#include "ispars/server/stop_signal.hpp"
#include "support/eventually.hpp"

namespace ispars::server {
namespace {

using namespace std::chrono_literals;
using test::eventually;

struct QuietInbox final : DaemonInbox {
  void receive(msg::QueryRequest) override {}
  void receive(msg::ChangeRequest) override {}
  void fleet_changed(const msg::DaemonInfo*) override {}
  void status_seen(const msg::SceneStatus&) override {}
  void task_seen(const msg::SceneTask&) override {}
};

class DdsLinkTest : public ::testing::Test {
 protected:
  DdsLinkTest() {
    config_.participant.domain = local::random_domain();  // locked for this process: no other test shares it
    config_.server_id = "link-test";
    config_.discovery_wait_ms = 0;
  }
  DaemonConfig config_;
  StopSignal stop_;
  QuietInbox inbox_;
  std::atomic<int> made_{0}, announced_{0}, republished_{0};
  DdsLink link_{config_,
                [this] {
                  ++made_;
                  return std::make_unique<DdsEndpoints>(inbox_, config_, 1);
                },
                stop_};
  void count_hooks() {
    link_.set_hooks({[this] { ++announced_; }, [this] { ++republished_; }});
  }
  int uses() {
    int n = 0;
    link_.with([&](DdsEndpoints&) { ++n; });
    return n;
  }
};

TEST_F(DdsLinkTest, NothingRunsOnAClosedLink) {
  EXPECT_EQ(uses(), 0);
  link_.send_reply(msg::Reply{});  // no participant: dropped, as after the stop
  link_.publish_status(msg::SceneStatus{});
  EXPECT_TRUE(link_.other_daemons().empty());
  link_.open();
  EXPECT_EQ(made_, 1);
  EXPECT_EQ(uses(), 1);
  link_.close();
  EXPECT_EQ(uses(), 0);
  link_.close();  // twice: nothing more
}

TEST_F(DdsLinkTest, StandingStillPastTheLeaseMakesANewParticipant) {
  count_hooks();
  link_.open();
  link_.rejoin_if_due();  // plain DDS, nothing stood still: no rejoin
  EXPECT_EQ(made_, 1);
  link_.note_stood_still(4000);
  link_.rejoin_if_due();  // the overlap: at least its listening time (nobody to hear)
  EXPECT_EQ(made_, 2);
  EXPECT_EQ(announced_, 2);  // from the new participant at once, and once the old one left
  EXPECT_EQ(republished_, 1);
  EXPECT_EQ(uses(), 1);
  link_.rejoin_if_due();  // taken: not again
  EXPECT_EQ(made_, 2);
}

TEST_F(DdsLinkTest, AStopEndsARejoinsOverlapAtOnce) {
  count_hooks();
  link_.open();
  link_.note_stood_still(4000);
  std::atomic<bool> done{false};
  std::thread fleet([&] {
    link_.rejoin_if_due();
    done = true;
  });
  ASSERT_TRUE(eventually([&] { return republished_ == 1; }, 30s, "the new participant republishes"));
  const auto stopped = std::chrono::steady_clock::now();
  stop_.stop();
  // Without the stop the overlap lasts its listening time (3 s) at least; the bound leaves room
  // for the old participant's deletion on a loaded machine.
  EXPECT_TRUE(eventually([&] { return done.load(); }, 2500ms, "the rejoin ends well within its listening time"));
  fleet.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - stopped).count();
  RecordProperty("rejoin_stop_seconds", std::to_string(seconds));
  EXPECT_EQ(made_, 2);
  EXPECT_EQ(uses(), 1);
}

}  // namespace
}  // namespace ispars::server
