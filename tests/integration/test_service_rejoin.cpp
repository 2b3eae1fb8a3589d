// A long-lived secured client that dropped a daemon which kept it (one-way loss: the client heard
// nothing from the daemon for longer than the lease, the daemon heard the client throughout).
// Debian's Fast DDS 2.9.1 cannot authenticate the two again while the daemon keeps its session
// (docs/service.md, "A stall under security"), and the daemon, which never lost the client, has
// no reason to rejoin: the client must, by itself, without losing its state. Here the test's own
// client and a replica of it, on a host of their own (tests/support/netns_lab.hpp), must answer
// and follow the scene again within a stated bound of the link coming back.

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "support/netns_lab.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;
// How soon after the link is back the client answers again: a peer's next announcement (lease/3
// in the lab's profile, 6.7 s), the grace a returned peer has to authenticate again (10 s), the
// rejoin, and a handshake.
constexpr std::chrono::seconds kHealBound{30};

class RejoinTest : public ServiceTest {};

TEST_F(RejoinTest, ASecuredClientThatDroppedADaemonWhichKeptItRejoinsByItself) {
  NetnsLab lab(dir_.path() / "netns", {"d1", "hc"}, kSecureLease);
  const auto keystore = client::make_keystore(std::string(ISPARS_SOURCE_DIR) + "/deploy/security/make-keystore.sh",
                                              dir_.path() / "keystore", {"daemon:d1", "operator:op", "viewer:probe"});
  const auto identity = [&](const std::string& name) { return (keystore / "identities" / name).string(); };
  lab.enter("hc");
  DaemonProcess daemon(ISPARS_DAEMON, domain_, dir_.path() / "data-d1", scene_dir_, "d1",
                       {"--profile-file", lab.profile("d1").string(), "--security", identity("d1")}, identity("probe"),
                       std::vector<std::string>{}, std::chrono::seconds(60), lab.prefix("d1"),
                       lab.profile("hc").string());
  client::ClientOptions options = client_options(domain_);
  options.participant.profile_file = lab.profile("hc").string();
  options.participant.security = identity("op");
  Client client(options);
  const std::string first_id = client.id();
  client.load("s0");
  client.build("s0", ispars_build(800, 3));
  msg::SceneStatus status = client.wait_idle("s0", {}, kLong);
  client::RoadmapReplica replica(client, "s0");
  ASSERT_TRUE(replica.wait_for(status.generation(), status.version(), std::chrono::seconds(60))) << replica.last_error();

  lab.deafen("hc", "d1");
  // The client drops the daemon once its lease runs out here; the daemon keeps the client.
  const auto deaf_at = Clock::now();
  while (Clock::now() - deaf_at < kSecureLease + std::chrono::seconds(30) && !client.daemon_identity("d1").empty()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_TRUE(client.daemon_identity("d1").empty()) << "the client never dropped the daemon";
  std::this_thread::sleep_for(std::chrono::seconds(2));
  lab.undeafen("hc", "d1");
  const auto heard_at = Clock::now();
  double answered_s = -1.0;
  while (Clock::now() - heard_at < kHealBound + std::chrono::seconds(40)) {
    try {
      if (client.stats("s0").server_id() == "d1") {
        answered_s = std::chrono::duration<double>(Clock::now() - heard_at).count();
        break;
      }
    } catch (const ClientError&) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_GE(answered_s, 0.0) << "the client never heard the daemon again";
  // The same client, with a new participant (the daemon still holds the old one's session).
  EXPECT_NE(client.id(), first_id);
  EXPECT_EQ(client.rejoins(), 1u);
  client.extend("s0", 300);
  status = client.wait_idle("s0", {}, kLong);
  EXPECT_EQ(status.samples_done(), 1100u);
  ASSERT_TRUE(replica.wait_for(status.generation(), status.version(), std::chrono::seconds(60))) << replica.last_error();
  const double followed_s = std::chrono::duration<double>(Clock::now() - heard_at).count();
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client.snapshot("s0").roadmap));
  std::printf("one-way loss for %.0f s: the client answered %.2f s after the link came back (bound %lld s); its "
              "replica followed an extend %.2f s after\n",
              std::chrono::duration<double>(heard_at - deaf_at).count(), answered_s,
              static_cast<long long>(kHealBound.count()), followed_s);
  EXPECT_LT(answered_s, static_cast<double>(kHealBound.count()));
  EXPECT_TRUE(daemon.alive());
  EXPECT_EQ(daemon.log().find("rejoining DDS domain"), std::string::npos) << "the daemon rejoined: it lost the client";
}

}  // namespace
}  // namespace ispars::test
