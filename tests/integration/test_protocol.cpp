// The protocol version, checked on both sides: a daemon answers a request of another version
// with an error naming both versions (not a timeout), and a client refuses, before sending, to
// address a daemon that announces another version. And the sender's identity, taken from the
// transport: a request that claims another client's id is answered to its real sender.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "ispars/client/client.hpp"
#include "ispars/client/wire_calls.hpp"
#include "ispars/local/local_daemon.hpp"
#include "ispars/roadmap/sealed_file.hpp"
#include "ispars/wire/convert.hpp"
#include "support/eventually.hpp"
#include "support/raw_peer.hpp"
#include "support/test_support.hpp"

namespace ispars::test {
namespace {

using namespace std::chrono_literals;

using client::Client;
using client::ClientError;
using client::SceneStatus;

class ProtocolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = local::random_domain();
    local::write_tank_tower_scenes(dir_.path() / "scenes", {"s0"});
  }
  TempDir dir_;
  int domain_ = 0;
};

TEST_F(ProtocolTest, ADaemonRefusesAnotherVersionByNameAndAnswersItsOwn) {
  local::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d");
  RawPeer peer(domain_);
  msg::QueryRequest request = client::make_query(msg::LIST_SCENES, "");
  request.server_id("d");
  request.request_seq(1);
  request.protocol(msg::PROTOCOL_VERSION + 1);
  const auto refused = peer.send(request, std::chrono::seconds(30));
  ASSERT_TRUE(refused.has_value()) << "no reply: a version mismatch must be an error, not a timeout";
  EXPECT_FALSE(refused->ok());
  EXPECT_NE(refused->error().find(fmt::format("request: protocol: this daemon speaks ispars protocol {}, the request "
                                              "protocol {}",
                                              msg::PROTOCOL_VERSION, msg::PROTOCOL_VERSION + 1)),
            std::string::npos)
      << refused->error();
  EXPECT_EQ(refused->protocol(), msg::PROTOCOL_VERSION);
  EXPECT_EQ(refused->body()._d(), msg::LIST_SCENES);
  request.request_seq(2);
  request.protocol(msg::PROTOCOL_VERSION);
  const auto answered = peer.send(request, std::chrono::seconds(30));
  ASSERT_TRUE(answered.has_value());
  EXPECT_TRUE(answered->ok()) << answered->error();
  ASSERT_EQ(answered->body()._d(), msg::LIST_SCENES);
  ASSERT_EQ(answered->body().list_scenes().scenes().size(), 1u);
  EXPECT_EQ(answered->body().list_scenes().scenes()[0].scene(), "s0");
  EXPECT_TRUE(daemon.alive());
}

TEST_F(ProtocolTest, AClientRefusesToAddressADaemonOfAnotherVersion) {
  RawPeer future(domain_);
  msg::DaemonInfo info;
  info.server_id("future");
  info.protocol(msg::PROTOCOL_VERSION + 1);
  info.host("elsewhere");
  future.announce(info);
  auto options = local::local_client_options(domain_);
  options.timeout = std::chrono::seconds(20);
  Client client(options);
  try {
    (void)call(client, client::make_query(msg::LIST_SCENES, ""), "future");
    ADD_FAILURE() << "a daemon of another protocol version was addressed";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.kind(), ClientError::Kind::protocol);
    EXPECT_NE(std::string(e.what()).find(fmt::format("daemon future speaks ispars protocol {}; this client speaks {}",
                                                     msg::PROTOCOL_VERSION + 1, msg::PROTOCOL_VERSION)),
              std::string::npos)
        << e.what();
  }
}

TEST_F(ProtocolTest, TheSenderIsWhoTheTransportSaysNotWhatTheRequestClaims) {
  local::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d");
  RawPeer victim(domain_), impostor(domain_);
  ASSERT_NE(victim.identity(), impostor.identity());
  // The impostor claims the victim's id for a STATS with sequence number 7.
  msg::QueryRequest forged = client::make_query(msg::STATS, "s0");
  forged.client_id(victim.identity());
  forged.server_id("d");
  forged.request_seq(7);
  forged.protocol(msg::PROTOCOL_VERSION);
  ASSERT_TRUE(impostor.post(forged));
  (void)eventually([&] { return impostor.replies_received() > 0; }, 10s, "the impostor is answered");  // checked below
  ASSERT_EQ(impostor.replies_received(), 1u) << "the reply went to the claimed id, not to its sender";
  EXPECT_EQ(impostor.replies()[0].client_id(), impostor.identity());
  // The victim's own request 7 is its own: answered afresh, not from the impostor's entry.
  msg::QueryRequest own = client::make_query(msg::LIST_SCENES, "");
  own.server_id("d");
  own.request_seq(7);
  own.protocol(msg::PROTOCOL_VERSION);
  const auto reply = victim.send(own, std::chrono::seconds(30));
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->ok()) << reply->error();
  EXPECT_EQ(reply->body()._d(), msg::LIST_SCENES) << "the victim got the impostor's cached reply";
  EXPECT_EQ(victim.replies_received(), 1u) << "the victim also received the impostor's reply";
}

}  // namespace
}  // namespace ispars::test

namespace ispars::test {
namespace {

// DDS-RPC 1.0 sec. 7.6.2: a reply written before the client's reply reader matched is lost (the
// reply topic is volatile). The daemon holds it until that reader matches, up to 2 s, and answers
// other clients meanwhile. The requests are posted once, never retried, so a reply written early
// is a reply lost.
TEST_F(ProtocolTest, AReplyIsHeldUntilTheClientsReaderMatchedAndNoLonger) {
  local::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d");
  Client client(local::local_client_options(domain_));
  client.load("s0");
  msg::QueryRequest stats = client::make_query(msg::STATS, "s0");
  stats.server_id("d");
  stats.protocol(msg::PROTOCOL_VERSION);
  stats.request_seq(1);

  RawPeer slow(domain_, "", /*read_replies=*/false);
  stats.client_id(slow.identity());
  ASSERT_TRUE(slow.post(stats));
  RawPeer late(domain_, "", /*read_replies=*/false);
  stats.client_id(late.identity());
  ASSERT_TRUE(late.post(stats));
  // While both replies wait, another client is answered at once.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(client.stats("s0").scene, "s0");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(1500));

  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // the reader comes late: 0.5 s
  slow.open_reply_reader();                                     // within the bound: the held reply reaches it
  ASSERT_TRUE(eventually([&] { return slow.replies_to(1) == 1u; }, 3s, "the held reply reaches the late reader", 10ms))
      << "the reply was written before the client's reader matched, and lost";
  ASSERT_TRUE(slow.reply_to(1)->ok()) << slow.reply_to(1)->error();
  EXPECT_EQ(slow.reply_to(1)->status().scene(), "s0");

  std::this_thread::sleep_for(std::chrono::milliseconds(2300));  // the reader comes later: past the 2 s bound
  late.open_reply_reader();
  EXPECT_TRUE(throughout([&] { return late.replies_to(1) == 0u; }, 1s, "no reply held past its bound"));
  EXPECT_NE(daemon.log().find(fmt::format("client {}'s reply reader has not acknowledged its route", late.identity())),
            std::string::npos)
      << daemon.log();
  // A client that gave up on the wait is answered when it asks again.
  stats.request_seq(2);
  const auto again = late.send(stats, std::chrono::seconds(30));
  ASSERT_TRUE(again.has_value());
  EXPECT_TRUE(again->ok()) << again->error();
}

// A change is kept in the daemon's ledger from before it is made. A client that resends it to the
// daemon after a restart (the same client, the same sequence number: its reply was lost) gets the
// first answer and the roadmap is not extended twice (before, the cache was in memory, and the
// resent EXTEND ran again: 2,000 samples). A change the daemon began and never answered is
// refused as interrupted, naming how to check.
TEST_F(ProtocolTest, AChangeResentAfterARestartIsAnsweredFromTheLedgerNotDoneTwice) {
  const auto data = dir_.path() / "data";
  auto daemon = std::make_unique<local::LocalDaemon>(ISPARS_DAEMON, domain_, data, dir_.path() / "scenes", "d");
  RawPeer peer(domain_);
  {
    Client client(local::local_client_options(domain_));
    client.load("s0");
    client::BuildArgs build;
    build.samples = 1000;
    client.build("s0", build);
    ASSERT_EQ(client.wait_idle("s0", {}, std::chrono::seconds(60)).samples_done, 1000u);
  }
  msg::ChangeRequest extend = client::make_change(msg::EXTEND, "s0");
  extend.args().extend().samples(500);
  extend.server_id("d");
  extend.protocol(msg::PROTOCOL_VERSION);
  extend.request_seq(11);
  const auto first = peer.send(extend, std::chrono::seconds(30));
  ASSERT_TRUE(first.has_value());
  ASSERT_TRUE(first->ok()) << first->error();
  ASSERT_EQ(daemon->terminate(), 0);
  // A begun change never answered, as a kill between the two records leaves it.
  {
    std::ofstream ledger(data / ".changes.log", std::ios::app);
    ledger << seal_json({{"begun", "EXTEND"}, {"client", peer.identity()}, {"seq", 12}, {"scene", "s0"}}).dump()
           << "\n";
  }
  daemon = std::make_unique<local::LocalDaemon>(ISPARS_DAEMON, domain_, data, dir_.path() / "scenes", "d");
  Client client(local::local_client_options(domain_));
  client.load("s0");
  ASSERT_EQ(client.wait_idle("s0", {}, std::chrono::seconds(60)).samples_done, 1500u) << "the extend, done once";
  extend.client_id(peer.identity());
  ASSERT_TRUE(peer.post(extend));
  ASSERT_TRUE(eventually([&] { return peer.replies_to(11) >= 2; }, 30s, "the retry is answered", 10ms))
      << daemon->log();
  ASSERT_EQ(peer.replies_to(11), 2u) << daemon->log();
  EXPECT_TRUE(peer.reply_to(11)->ok());
  EXPECT_EQ(peer.reply_to(11)->message(), first->message());
  EXPECT_EQ(client.wait_idle("s0", {}, std::chrono::seconds(60)).samples_done, 1500u) << "the resent extend ran again";
  extend.request_seq(12);
  const auto interrupted = peer.send(extend, std::chrono::seconds(30));
  ASSERT_TRUE(interrupted.has_value());
  EXPECT_FALSE(interrupted->ok());
  EXPECT_NE(interrupted->error().find("interrupted: daemon d stopped while it was doing this EXTEND of scene 's0'"),
            std::string::npos)
      << interrupted->error();
  // Nothing was done again: a new request after both is the only one that extends.
  extend.request_seq(13);
  const auto fresh = peer.send(extend, std::chrono::seconds(30));
  ASSERT_TRUE(fresh.has_value());
  ASSERT_TRUE(fresh->ok()) << fresh->error();
  EXPECT_EQ(client.wait_idle("s0", {}, std::chrono::seconds(60)).samples_done, 2000u);
}

TEST_F(ProtocolTest, ARetryIsAnsweredFromTheCacheNotServedAgain) {
  local::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d");
  Client client(local::local_client_options(domain_));
  client.load("s0");
  RawPeer peer(domain_);
  msg::QueryRequest stats = client::make_query(msg::STATS, "s0");
  stats.server_id("d");
  stats.protocol(msg::PROTOCOL_VERSION);
  stats.request_seq(7);
  const auto first = peer.send(stats, std::chrono::seconds(30));
  ASSERT_TRUE(first.has_value());
  ASSERT_TRUE(first->ok()) << first->error();
  // Two retries of #7: each answered, with the very reply of the first (a status served again
  // would carry a later status_seq).
  ASSERT_TRUE(peer.post(stats));
  ASSERT_TRUE(peer.post(stats));
  EXPECT_TRUE(eventually([&] { return peer.replies_to(7) == 3; }, 5s, "both retries are answered", 10ms));
  ASSERT_TRUE(peer.reply_to(7).has_value());
  EXPECT_EQ(peer.reply_to(7)->status().status_seq(), first->status().status_seq());
  stats.request_seq(8);  // a new request is served anew
  const auto next = peer.send(stats, std::chrono::seconds(30));
  ASSERT_TRUE(next.has_value());
  EXPECT_GT(next->status().status_seq(), first->status().status_seq());
}

}  // namespace
}  // namespace ispars::test

namespace ispars::test {
namespace {

TEST_F(ProtocolTest, ARoadmapOfSeveralMegabytesTravelsInChunksAtOneVersion) {
  local::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d",
                            {"--memory-budget-mb", "1073741824"});
  Client client(local::local_client_options(domain_));
  client.load("s0");
  client::BuildArgs dense;
  dense.method = BuildMethod::dense;  // every pair within delta: many edges, a large encoding
  dense.samples = 15000;
  client.build("s0", dense);
  const SceneStatus built = client.wait_idle("s0", {}, std::chrono::minutes(5));
  RawPeer peer(domain_);
  msg::QueryRequest first = client::make_query(msg::SNAPSHOT, "s0");
  first.server_id("d");
  first.protocol(msg::PROTOCOL_VERSION);
  first.request_seq(1);
  const auto chunk0 = peer.send(first, std::chrono::seconds(30));
  ASSERT_TRUE(chunk0.has_value());
  ASSERT_TRUE(chunk0->ok()) << chunk0->error();
  const std::uint32_t chunks = chunk0->body().snapshot().chunk_count();
  EXPECT_GE(chunks, 2u) << "the roadmap fits one chunk: the test needs a larger one";
  // The client pulls every chunk at chunk 0's version and decodes the whole roadmap.
  const client::Snapshot whole = client.snapshot("s0");
  EXPECT_EQ(whole.version, built.version);
  EXPECT_EQ(whole.roadmap.vertex_count(), built.vertices);
  EXPECT_EQ(whole.roadmap.edge_count(), built.edges);
  // Past the last chunk: an error naming the field, not a hang.
  msg::QueryRequest past = first;
  past.request_seq(2);
  past.args().snapshot().version(chunk0->body().snapshot().version());
  past.args().snapshot().generation(chunk0->body().snapshot().generation());
  past.args().snapshot().chunk_index(chunks);
  const auto refused = peer.send(past, std::chrono::seconds(30));
  ASSERT_TRUE(refused.has_value());
  EXPECT_FALSE(refused->ok());
  EXPECT_NE(refused->error().find("chunk"), std::string::npos) << refused->error();
}

}  // namespace
}  // namespace ispars::test
