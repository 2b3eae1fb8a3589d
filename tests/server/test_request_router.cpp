// The request router without DDS: header checks named, retries answered from the cache, a query
// on the change topic refused, and a full slow lane refusing at once while the quick lane answers.

#include "ispars/server/request_router.hpp"

#include <gtest/gtest.h>

#include "server/recording_outbox.hpp"
#include "server/unit_service.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::server {
namespace {

using namespace std::chrono_literals;
using test::eventually;

class RequestRouterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_tank_scenes(dir_.path(), {"s0", "s1"});
    service_ = std::make_unique<service::RoadmapService>(test::unit_service_settings(dir_.path(), "d1"),
                                                         service::ServiceEvents{});
  }
  std::unique_ptr<RequestRouter> router(std::size_t queue = 16) {
    return std::make_unique<RequestRouter>(
        RequestRouter::Parts{"d1", queue, *service_, statuses_, out_, metrics_, gate_,
                             [](const std::string& scene) { return scene == "s1" ? "a note" : ""; }},
        std::make_unique<RequestLedger>(dir_.path() / "data"));
  }
  template <class Request>
  static Request request(std::uint64_t seq, const std::string& scene, std::string client = "c1") {
    Request r;
    r.client_id(client);
    r.request_seq(seq);
    r.server_id("d1");
    r.protocol(msg::PROTOCOL_VERSION);
    r.scene(scene);
    return r;
  }
  static msg::QueryRequest query(std::uint64_t seq, msg::Operation op, const std::string& scene = "") {
    msg::QueryRequest r = request<msg::QueryRequest>(seq, scene);
    if (op == msg::LIST_SCENES) r.args().list_scenes(msg::NoArgs{});
    if (op == msg::STATS) r.args().stats(msg::NoArgs{});
    if (op == msg::TASK_LIST) r.args().task_list(msg::NoArgs{});
    return r;
  }
  static msg::ChangeRequest load(std::uint64_t seq, const std::string& scene) {
    msg::ChangeRequest r = request<msg::ChangeRequest>(seq, scene);
    r.args().load_scene(msg::NoArgs{});
    return r;
  }
  // The reply to request `seq`, once one came (a failure of the test after 30 s).
  msg::Reply reply(std::uint64_t seq, std::size_t nth = 0) {
    msg::Reply found;
    EXPECT_TRUE(eventually(
        [&] {
          std::size_t seen = 0;
          for (const msg::Reply& r : out_.replies()) {
            if (r.request_seq() == seq && seen++ == nth) {
              found = r;
              return true;
            }
          }
          return false;
        },
        30s, "a reply to #" + std::to_string(seq)));
    return found;
  }

  test::TempDir dir_;
  test::RecordingOutbox out_;
  DaemonMetrics metrics_;
  std::atomic<bool> leaving_{false};
  TakeoverGate gate_;
  std::unique_ptr<service::RoadmapService> service_;
  StatusPublisher statuses_{"d1", out_, metrics_, leaving_};
};

TEST_F(RequestRouterTest, AQueryIsAnsweredFromTheService) {
  auto r = router();
  r->receive(query(1, msg::LIST_SCENES));
  const msg::Reply list = reply(1);
  ASSERT_TRUE(list.ok()) << list.error();
  EXPECT_EQ(list.server_id(), "d1");
  EXPECT_EQ(list.client_id(), "c1");
  ASSERT_EQ(list.body().list_scenes().scenes().size(), 2u);
  EXPECT_EQ(list.body().list_scenes().scenes()[1].note(), "a note");
  r->receive(load(2, "s0"));
  const msg::Reply loaded = reply(2);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded.status().scene(), "s0");
  EXPECT_EQ(service_->loaded_scenes(), std::vector<std::string>{"s0"});
}

TEST_F(RequestRouterTest, EveryBadHeaderIsRefusedByName) {
  auto r = router();
  msg::QueryRequest old = query(1, msg::LIST_SCENES);
  old.protocol(msg::PROTOCOL_VERSION - 1);
  r->receive(old);
  EXPECT_NE(reply(1).error().find("request: protocol: this daemon speaks ispars protocol"), std::string::npos);
  r->receive(query(0, msg::LIST_SCENES));
  EXPECT_NE(reply(0).error().find("request: request_seq: 0 is reserved"), std::string::npos);
  msg::ChangeRequest verify_on_change = request<msg::ChangeRequest>(2, "s0");
  verify_on_change.args().cancel(msg::NoArgs{});
  verify_on_change.args()._d() = msg::VERIFY;
  r->receive(verify_on_change);
  EXPECT_NE(reply(2).error().find("request: operation: verify is not a change"), std::string::npos);
  // No client id: nowhere to answer, so nothing is sent.
  msg::QueryRequest anonymous = query(3, msg::LIST_SCENES);
  anonymous.client_id("");
  r->receive(anonymous);
  r->receive(query(4, msg::LIST_SCENES));
  (void)reply(4);
  for (const msg::Reply& each : out_.replies()) EXPECT_NE(each.request_seq(), 3u);
  EXPECT_TRUE(service_->loaded_scenes().empty());  // nothing changed
}

TEST_F(RequestRouterTest, ARetryIsAnsweredFromTheCacheAndNotRunAgain) {
  auto r = router();
  r->receive(load(1, "s0"));
  const msg::Reply first = reply(1);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first.message(), "loaded scene 's0'");
  r->receive(load(1, "s0"));  // the same id: a retry, whose first reply was lost
  const msg::Reply again = reply(1, 1);
  EXPECT_EQ(again.message(), "loaded scene 's0'");  // run again, it would say "already loaded"
  r->receive(load(2, "s0"));
  EXPECT_EQ(reply(2).message(), "scene 's0' was already loaded");
}

TEST_F(RequestRouterTest, AFullSlowLaneRefusesAtOnceWhileTheQuickLaneAnswers) {
  auto r = router(1);
  auto held =
      std::make_unique<TakeoverGate::Held>(gate_, "s0");  // slow requests for s0 wait in their lane (at most 2 s each)
  constexpr std::uint64_t kSlow = 12;
  for (std::uint64_t seq = 1; seq <= kSlow; ++seq) r->receive(query(seq, msg::TASK_LIST, "s0"));
  // At most two run and one waits (fewer when a thread had not yet taken its request): the
  // others are refused as busy, each at once.
  std::size_t busy = 0;
  ASSERT_TRUE(eventually(
      [&] {
        busy = 0;
        for (const msg::Reply& each : out_.replies()) {
          if (each.error().find("busy: 1 requests are queued on this daemon's slow lane") != std::string::npos) ++busy;
        }
        return busy >= kSlow - 3;
      },
      30s, "the requests past the slow lane's room refused as busy"));
  r->receive(query(100, msg::STATS, "s1"));  // the quick lane answers now, however full the slow one
  const msg::Reply stats = reply(100);
  EXPECT_NE(stats.error().find("not loaded"), std::string::npos) << stats.error();
  // Those that took the lane's room answer once the gate lets them by.
  held.reset();
  for (std::uint64_t seq = 1; seq <= kSlow; ++seq) (void)reply(seq);
  std::size_t answered = 0;
  for (const msg::Reply& each : out_.replies()) {
    if (each.request_seq() <= kSlow && each.error().find("busy") == std::string::npos) {
      ++answered;
      EXPECT_NE(each.error().find("not loaded"), std::string::npos) << each.error();
    }
  }
  EXPECT_GE(answered, 1u);
  EXPECT_LE(answered, 3u);
}

}  // namespace
}  // namespace ispars::server
