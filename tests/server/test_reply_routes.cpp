// ReplyRoutes in one process over real Fast DDS (localhost): each client's replies reach the
// reader in its partition and no other, a route is ready only once its reader acknowledged it,
// routes are released when asked (their reader left), when they never match, and past the bound.

#include <gtest/gtest.h>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <chrono>
#include <thread>

#include "ispars/local/local_daemon.hpp"
#include "ispars/server/reply_routes.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"
#include "support/eventually.hpp"

namespace ispars::server {
namespace {

namespace fdds = eprosima::fastdds::dds;

struct Routes {
  explicit Routes(std::size_t max) : participant({domain, "", "ispars", "routes", ""}) {
    reply_topic = wire::find_or_create_topic(participant.get(), reply_type, wire::kReplyTopic);
    progress_topic = wire::find_or_create_topic(participant.get(), progress_type, wire::kTourProgressTopic);
    routes = std::make_unique<ReplyRoutes>(participant.get(), reply_topic, progress_topic, nullptr, "daemon", max);
  }
  int domain = local::random_domain();  // locked for this process: no other test shares it
  wire::Participant participant;
  fdds::TypeSupport reply_type{new msg::ReplyPubSubType()};
  fdds::TypeSupport progress_type{new msg::TourProgressPubSubType()};
  fdds::Topic* reply_topic = nullptr;
  fdds::Topic* progress_topic = nullptr;
  std::unique_ptr<ReplyRoutes> routes;
};

// A client's reply reader in the partition of `identity`, on its own participant.
struct ClientReader {
  ClientReader(int domain, const std::string& identity) : participant({domain, "", "ispars", "reader", ""}) {
    fdds::Topic* topic = wire::find_or_create_topic(participant.get(), type, wire::kReplyTopic);
    fdds::Subscriber* sub = participant->create_subscriber(wire::reply_subscriber_qos(identity));
    reader = sub->create_datareader(topic, wire::request_reply_reader_qos());
  }
  // Takes every reply; returns how many have a sequence number of at least `from` (and at most `to`).
  std::size_t take_all(std::uint64_t from = 0, std::uint64_t to = ~std::uint64_t{0}) {
    std::size_t n = 0;
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      n += info.valid_data && reply.request_seq() >= from && reply.request_seq() <= to ? 1 : 0;
    }
    return n;
  }
  wire::Participant participant;
  fdds::TypeSupport type{new msg::ReplyPubSubType()};
  fdds::DataReader* reader = nullptr;
};

msg::Reply reply_to(const std::string& client, std::uint64_t seq) {
  msg::Reply r;
  r.client_id(client);
  r.request_seq(seq);
  r.ok(true);
  return r;
}

// Services the routes until `client`'s is ready (at most 5 s).
bool serve_until_ready(ReplyRoutes& routes, const std::string& client) {
  return test::eventually(
      [&] {
        routes.service();
        return routes.ready(client);
      },
      std::chrono::seconds(5), "the route of " + client + " is ready", std::chrono::milliseconds(2));
}

TEST(ReplyRoutes, AReplyReachesTheReaderInItsClientsPartitionAndNoOther) {
  Routes r(8);
  ClientReader a(r.domain, "aaaa"), b(r.domain, "bbbb");
  r.routes->want("aaaa");
  ASSERT_TRUE(serve_until_ready(*r.routes, "aaaa")) << "the reader never acknowledged the route";
  // Ready means acknowledged: every reply from now on arrives, the first included, with no retry.
  for (std::uint64_t seq = 1; seq <= 10; ++seq) ASSERT_TRUE(r.routes->write_reply(reply_to("aaaa", seq)));
  std::size_t got = 0;
  (void)test::eventually(
      [&] {
        got += a.take_all(1);  // the route-open reply (0) aside
        return got >= 10;
      },
      std::chrono::seconds(3), "ten replies", std::chrono::milliseconds(10));
  EXPECT_EQ(got, 10u);
  fdds::SubscriptionMatchedStatus bs;
  b.reader->get_subscription_matched_status(bs);
  EXPECT_EQ(bs.current_count, 0);
  EXPECT_EQ(b.take_all(), 0u);
}

TEST(ReplyRoutes, ARouteIsReadyOnlyOnceItsReaderHasAcknowledgedIt) {
  Routes r(8);
  r.routes->want("cccc");
  for (int i = 0; i < 100; ++i) {
    r.routes->service();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  EXPECT_TRUE(r.routes->has("cccc"));
  EXPECT_FALSE(r.routes->ready("cccc")) << "no reader: nothing acknowledged the route";
  ClientReader c(r.domain, "cccc");
  ASSERT_TRUE(serve_until_ready(*r.routes, "cccc"));
  // The reader got the route-open reply, request_seq 0, which no request has.
  std::size_t markers = 0;
  (void)test::eventually(
      [&] {
        markers += c.take_all(0, 0);
        return markers > 0;
      },
      std::chrono::seconds(3), "the route-open reply", std::chrono::milliseconds(10));
  EXPECT_EQ(markers, 1u);
  EXPECT_EQ(r.routes->ready_count(), 1u);
}

TEST(ReplyRoutes, AtTheBoundTheLeastRecentlyUsedRouteIsReleased) {
  Routes r(2);
  r.routes->want("a");
  r.routes->want("b");
  r.routes->service();
  ASSERT_TRUE(r.routes->write_reply(reply_to("a", 1)));  // a is now the more recent
  r.routes->want("c");
  r.routes->service();
  EXPECT_EQ(r.routes->size(), 2u);
  EXPECT_TRUE(r.routes->has("a"));
  EXPECT_FALSE(r.routes->has("b"));
  EXPECT_TRUE(r.routes->has("c"));
  EXPECT_FALSE(r.routes->write_reply(reply_to("b", 1))) << "no route, no reply: the sender thread asks for one";
}

TEST(ReplyRoutes, ARouteIsReleasedWhenItsReaderLeavesInTheOrderAsked) {
  Routes r(8);
  r.routes->want("a");
  r.routes->want("b");
  r.routes->forget("b");
  r.routes->forget("x");  // never had one
  EXPECT_TRUE(r.routes->has_work());
  r.routes->service();
  EXPECT_FALSE(r.routes->has_work());
  EXPECT_TRUE(r.routes->has("a"));
  EXPECT_FALSE(r.routes->has("b"));
  r.routes->forget("a");
  r.routes->want("a");  // asked again after: it stays
  r.routes->service();
  EXPECT_TRUE(r.routes->has("a"));
  EXPECT_EQ(r.routes->size(), 1u);
}

TEST(ReplyRoutes, ARouteThatNeverMatchesAReaderIsReleasedAfterItsLifetime) {
  Routes r(8);
  const auto t0 = ReplyRoutes::Clock::now();
  r.routes->want("gone");
  r.routes->service(t0);
  r.routes->service(t0 + ReplyRoutes::kUnmatchedLifetime - std::chrono::milliseconds(1));
  EXPECT_TRUE(r.routes->has("gone"));
  r.routes->service(t0 + ReplyRoutes::kUnmatchedLifetime);
  EXPECT_FALSE(r.routes->has("gone"));
}

TEST(ReplyRoutes, ProgressForAClientWithoutARouteAsksForOne) {
  Routes r(8);
  msg::TourProgress progress;
  progress.client_id("pppp");
  r.routes->write_progress(progress);
  EXPECT_TRUE(r.routes->has_work());
  r.routes->service();
  EXPECT_TRUE(r.routes->has("pppp"));
}

}  // namespace
}  // namespace ispars::server
