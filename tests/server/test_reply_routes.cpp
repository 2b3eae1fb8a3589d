// ReplyRoutes in one process over real Fast DDS (localhost): each client's replies reach the
// reader in its partition and no other, and the number of routes is bounded, releasing first the
// clients whose reader left, then the least recently used.

#include <gtest/gtest.h>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <chrono>
#include <thread>

#include "isparsPubSubTypes.h"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "reply_routes.hpp"
#include "support/local_daemon.hpp"

namespace ispars::server {
namespace {

namespace fdds = eprosima::fastdds::dds;

struct Routes {
  explicit Routes(std::size_t max) : participant({domain, "", "ispars", "routes", ""}) {
    reply_topic = wire::find_or_create_topic(participant.get(), reply_type, wire::kReplyTopic);
    progress_topic = wire::find_or_create_topic(participant.get(), progress_type, wire::kTourProgressTopic);
    routes = std::make_unique<ReplyRoutes>(participant.get(), reply_topic, progress_topic, nullptr, max);
  }
  int domain = client::random_domain();  // locked for this process: no other test shares it
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
  // Takes every reply; returns how many have a sequence number of at least `from`.
  std::size_t take_all(std::uint64_t from = 0) {
    std::size_t n = 0;
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      n += info.valid_data && reply.request_seq() >= from ? 1 : 0;
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

TEST(ReplyRoutes, AReplyReachesTheReaderInItsClientsPartitionAndNoOther) {
  Routes r(8);
  ClientReader a(r.domain, "aaaa"), b(r.domain, "bbbb");
  ASSERT_TRUE(r.routes->open("aaaa"));
  // Until the match is seen from both ends (discovery is not symmetric in time: a reply written
  // before the writer knows the reader is lost, as for any volatile writer). The writer end is
  // seen by a first reply arriving; replies 1.. are then sent and must all arrive.
  std::size_t got = 0;
  for (int i = 0; i < 500 && got == 0; ++i) {
    ASSERT_TRUE(r.routes->write_reply(reply_to("aaaa", 0)));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    got = a.take_all();
  }
  ASSERT_GT(got, 0u) << "the route never matched the client's reader";
  got = 0;
  for (std::uint64_t seq = 1; seq <= 10; ++seq) ASSERT_TRUE(r.routes->write_reply(reply_to("aaaa", seq)));
  for (int i = 0; i < 300 && got < 10; ++i) {
    got += a.take_all(1);  // late copies of the probe (0) aside
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(got, 10u);
  fdds::SubscriptionMatchedStatus bs;
  b.reader->get_subscription_matched_status(bs);
  EXPECT_EQ(bs.current_count, 0);
  EXPECT_EQ(b.take_all(), 0u);
}

TEST(ReplyRoutes, AtTheBoundTheLeastRecentlyUsedRouteIsReleased) {
  Routes r(2);
  ASSERT_TRUE(r.routes->open("a"));
  ASSERT_TRUE(r.routes->open("b"));
  ASSERT_TRUE(r.routes->open("a"));  // a is now the more recent
  ASSERT_TRUE(r.routes->open("c"));
  EXPECT_EQ(r.routes->size(), 2u);
  EXPECT_TRUE(r.routes->has("a"));
  EXPECT_FALSE(r.routes->has("b"));
  EXPECT_TRUE(r.routes->has("c"));
}

TEST(ReplyRoutes, AClientWhoseReaderLeftIsReleasedFirst) {
  Routes r(2);
  ASSERT_TRUE(r.routes->open("a"));
  ASSERT_TRUE(r.routes->open("b"));
  r.routes->reader_left("b");  // b is more recent than a, but gone
  ASSERT_TRUE(r.routes->open("c"));
  EXPECT_TRUE(r.routes->has("a"));
  EXPECT_FALSE(r.routes->has("b"));
  EXPECT_TRUE(r.routes->has("c"));
  // A reply to a released client opens its route again (and releases another).
  EXPECT_TRUE(r.routes->write_reply(reply_to("b", 1)));
  EXPECT_TRUE(r.routes->has("b"));
  EXPECT_EQ(r.routes->size(), 2u);
}

}  // namespace
}  // namespace ispars::server
