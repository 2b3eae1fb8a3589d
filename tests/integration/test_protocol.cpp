// The protocol version, checked on both sides: a daemon answers a request of another version
// with an error naming both versions (not a timeout), and a client refuses, before sending, to
// address a daemon that announces another version.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "ispars/client/client.hpp"
#include "ispars/wire/convert.hpp"
#include "support/local_daemon.hpp"
#include "support/raw_peer.hpp"
#include "support/test_support.hpp"

namespace ispars::test {
namespace {

using client::Client;
using client::ClientError;

class ProtocolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = client::random_domain();
    client::write_tank_tower_scenes(dir_.path() / "scenes", {"s0"});
  }
  TempDir dir_;
  int domain_ = 0;
};

TEST_F(ProtocolTest, ADaemonRefusesAnotherVersionByNameAndAnswersItsOwn) {
  client::LocalDaemon daemon(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes", "d");
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
  EXPECT_EQ(answered->body().list_scenes().scenes()[0].name(), "s0");
  EXPECT_TRUE(daemon.alive());
}

TEST_F(ProtocolTest, AClientRefusesToAddressADaemonOfAnotherVersion) {
  RawPeer future(domain_);
  msg::DaemonInfo info;
  info.server_id("future");
  info.protocol(msg::PROTOCOL_VERSION + 1);
  info.host("elsewhere");
  future.announce(info);
  auto options = client::local_client_options(domain_);
  options.timeout = std::chrono::seconds(20);
  Client client(options);
  try {
    (void)client.call(client::make_query(msg::LIST_SCENES, ""), "future");
    ADD_FAILURE() << "a daemon of another protocol version was addressed";
  } catch (const ClientError& e) {
    EXPECT_EQ(e.kind(), ClientError::Kind::protocol);
    EXPECT_NE(std::string(e.what()).find(fmt::format("daemon future speaks ispars protocol {}; this client speaks {}",
                                                     msg::PROTOCOL_VERSION + 1, msg::PROTOCOL_VERSION)),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace ispars::test
