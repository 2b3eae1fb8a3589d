// Rejoining under DDS Security (docs/fleet.md, "Rejoining"), in network namespaces of the test's
// own (tests/support/netns_lab.hpp):
// - a long-lived secured client that dropped a daemon which kept it (one-way loss: the client
//   heard nothing from the daemon for longer than the lease, the daemon heard the client
//   throughout). Debian's Fast DDS 2.9.1 cannot authenticate the two again while the daemon keeps
//   its session (docs/service.md, "A stall under security"), and the daemon, which never lost the
//   client, has no reason to rejoin: the client must, by itself, without losing its state. The
//   client and a replica of it must answer and follow the scene again within a stated bound;
// - a secured daemon that rejoins while it holds a scene keeps it.

#include <gtest/gtest.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <thread>

#include "integration/metrics_probe.hpp"
#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "support/netns_lab.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
// How soon after the link is back the client answers again: a peer's next announcement (lease/3
// in the lab's profile, 6.7 s), the grace a returned peer has to authenticate again (10 s), the
// rejoin, and a handshake.
constexpr std::chrono::seconds kHealBound{30};
// How long two daemons' first handshake is kept from ending, and how soon after that they must
// have met: a rejoin due at most once per period (30 s), the grace (10 s), a handshake.
constexpr std::chrono::seconds kBlocked{25};
constexpr std::chrono::seconds kFirstMeetingBound{60};

class RejoinTest : public ServiceTest {};

// A transport identity as the daemon's log writes it: bytes dotted ("86f2" -> "86.f2").
std::string dotted(const std::string& identity) {
  std::string out;
  for (std::size_t i = 0; i < identity.size(); ++i) {
    if (i > 0 && i % 2 == 0) out.push_back('.');
    out.push_back(identity[i]);
  }
  return out;
}

TEST_F(RejoinTest, ASecuredClientThatDroppedADaemonWhichKeptItRejoinsByItself) {
  NetnsLab lab(dir_.path() / "netns", {"d1", "hc"}, kSecuredTestLease);
  const auto keystore = local::make_keystore(std::string(ISPARS_SOURCE_DIR) + "/deploy/security/make-keystore.sh",
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
  SceneStatus status = load_and_build(client, "s0", ispars_build(800, 3));
  client::RoadmapReplica replica(client, "s0");
  ASSERT_TRUE(replica.wait_for(status.generation, status.version, std::chrono::seconds(60))) << replica.last_error();

  lab.deafen("hc", "d1");
  // The client drops the daemon once its lease runs out here; the daemon keeps the client.
  const auto deaf_at = Clock::now();
  ASSERT_TRUE(eventually([&] { return client.daemon_identity("d1").empty(); }, kSecuredTestLease + 30s,
                         "the client drops the daemon", 200ms));
  std::this_thread::sleep_for(std::chrono::seconds(2));  // the fault goes on a while (not a wait for a condition)
  lab.undeafen("hc", "d1");
  const auto heard_at = Clock::now();
  ASSERT_TRUE(eventually(
      [&] {
        try {
          return client.stats("s0").server_id == "d1";
        } catch (const ClientError&) {
          return false;
        }
      },
      kHealBound + 40s, "the client hears the daemon again", 200ms));
  const double answered_s = std::chrono::duration<double>(Clock::now() - heard_at).count();
  // The same client, with a new participant (the daemon still holds the old one's session).
  EXPECT_NE(client.id(), first_id);
  EXPECT_EQ(client.rejoins(), 1u);
  client.extend("s0", 300);
  status = client.wait_idle("s0", {}, kLong);
  EXPECT_EQ(status.samples_done, 1100u);
  ASSERT_TRUE(replica.wait_for(status.generation, status.version, std::chrono::seconds(60))) << replica.last_error();
  const double followed_s = std::chrono::duration<double>(Clock::now() - heard_at).count();
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client.snapshot("s0").roadmap));
  std::printf(
      "one-way loss for %.0f s: the client answered %.2f s after the link came back (bound %lld s); its "
      "replica followed an extend %.2f s after\n",
      std::chrono::duration<double>(heard_at - deaf_at).count(), answered_s, static_cast<long long>(kHealBound.count()),
      followed_s);
  EXPECT_LT(answered_s, static_cast<double>(kHealBound.count()));
  EXPECT_TRUE(daemon.alive());
  EXPECT_EQ(daemon.log().find("rejoining DDS domain"), std::string::npos) << "the daemon rejoined: it lost the client";
}

// A secured daemon that rejoins (a new participant) while it holds a scene keeps it: its peers
// must not read the old participant's leave as the holder leaving. The owner is made deaf to the
// other daemon past the lease, so it drops the other, which kept it; once the link is back the
// two cannot authenticate again and the owner rejoins (docs/fleet.md, "Rejoining"). Found in CI
// (2026-11-27): a peer took the scene over 90 ms after the old participant left, and an extend
// sent to the owner was refused.
TEST_F(RejoinTest, ASecuredDaemonThatRejoinsKeepsItsScenes) {
  NetnsLab lab(dir_.path() / "netns", {"d1", "d2", "hc"}, kSecuredTestLease);
  const auto keystore =
      local::make_keystore(std::string(ISPARS_SOURCE_DIR) + "/deploy/security/make-keystore.sh",
                           dir_.path() / "keystore", {"daemon:d1", "daemon:d2", "operator:op", "viewer:probe"});
  const auto identity = [&](const std::string& name) { return (keystore / "identities" / name).string(); };
  lab.enter("hc");
  std::map<std::string, std::unique_ptr<DaemonProcess>> daemons;
  for (const std::string id : {"d1", "d2"}) {
    daemons[id] = std::make_unique<DaemonProcess>(
        ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id), scene_dir_, id,
        std::vector<std::string>{"--profile-file", lab.profile(id).string(), "--security", identity(id), "--metrics",
                                 lab.address(id) + ":0"},
        identity("probe"), std::vector<std::string>{}, std::chrono::seconds(60), lab.prefix(id),
        lab.profile("hc").string());
  }
  client::ClientOptions options = client_options(domain_);
  options.participant.profile_file = lab.profile("hc").string();
  options.participant.security = identity("op");
  Client client(options);
  ASSERT_TRUE(eventually([&] { return client.daemons().size() == 2; }, 30s, "the client hears both daemons"));
  // The premise: the two daemons met (each hears the other's announcements, so their secured
  // session works both ways) before the fault. Two daemons started together may not authenticate
  // each other at first (Fast DDS 2.9.1; the next test) and meet only once one of them rejoins: a
  // rejoin this test must not count as the owner's.
  std::map<std::string, int> ports;
  for (auto& [id, d] : daemons) ports[id] = metrics_port(d->log(), lab.address(id));
  const auto met = [&] {
    return other_daemons_counted_on(ports["d1"], lab.address("d1")) == 1 &&
           other_daemons_counted_on(ports["d2"], lab.address("d2")) == 1;
  };
  ASSERT_TRUE(eventually(met, kFirstMeetingBound, "the daemons meet", 200ms))
      << daemons["d1"]->log() << daemons["d2"]->log();
  const SceneStatus built = load_and_build(client, "s0", ispars_build(800, 3));
  const std::string owner = built.server_id;
  const std::string other = owner == "d1" ? "d2" : "d1";

  const std::string first_participant = client.daemon_identity(owner);
  ASSERT_FALSE(first_participant.empty());

  const std::size_t owner_log_before = daemons[owner]->log().size();
  lab.deafen(owner, other);  // the owner drops the other once its lease runs out; the other keeps it
  std::this_thread::sleep_for(kSecuredTestLease + std::chrono::seconds(5));  // the fault: past the lease
  lab.undeafen(owner, other);
  const auto healed = Clock::now();
  // The positive control: the owner did rejoin (else this test shows nothing).
  const auto rejoined = [&] {
    return daemons[owner]->log().find("rejoined DDS domain", owner_log_before) != std::string::npos;
  };
  ASSERT_TRUE(eventually(rejoined, 60s, "the owner rejoins", 200ms)) << daemons[owner]->log();
  const double rejoined_s = std::chrono::duration<double>(Clock::now() - healed).count();
  // The client hears the new participant's announcement a moment after the owner logs its rejoin
  // (secured: once the client has authenticated it).
  std::string second_participant;
  ASSERT_TRUE(eventually(
      [&] {
        second_participant = client.daemon_identity(owner);
        return !second_participant.empty() && second_participant != first_participant;
      },
      30s, "the client hears the owner's new participant", 100ms));
  ASSERT_NE(second_participant, first_participant);

  // Made before break: the other daemon authenticated the owner's new participant before the old
  // one left, so it never saw the owner gone. Broken (the old participant deleted first), the old
  // one leaves about 10 ms before the new one is even discovered; a peer whose handshake takes
  // longer than its fleet period (100 ms), as under load, takes the scene over.
  const std::string left = "participant " + dotted(first_participant) + " (isparsd " + owner + ") left";
  const std::string authenticated = "participant " + dotted(second_participant) + " authenticated";
  const auto seen = [&](const std::string& line) { return daemons[other]->log().find(line) != std::string::npos; };
  (void)eventually([&] { return seen(left) && seen(authenticated); }, 10s,
                   "the other daemon logs both");  // checked below
  const std::string log = daemons[other]->log();
  ASSERT_NE(log.find(left), std::string::npos) << log;
  ASSERT_NE(log.find(authenticated), std::string::npos) << log;
  EXPECT_LT(log.find(authenticated), log.find(left))
      << "the old participant left before daemon " << other << " heard the new one:\n"
      << log;

  // Served by the owner throughout: an extend sent to it is taken, and nothing moved.
  client.extend("s0", 200);
  const SceneStatus extended = client.wait_idle("s0", {}, kLong);
  EXPECT_EQ(extended.server_id, owner);
  EXPECT_EQ(extended.generation, built.generation);
  EXPECT_EQ(extended.samples_done, 1000u);
  EXPECT_EQ(daemons[other]->log().find("takes it over"), std::string::npos)
      << "daemon " << other << " took the scene over:\n"
      << daemons[other]->log();
  EXPECT_EQ(daemons[owner]->log().find("handed over to"), std::string::npos) << daemons[owner]->log();
  std::printf("daemon %s rejoined %.1f s after the link came back and kept scene s0\n", owner.c_str(), rejoined_s);
  for (auto& [id, d] : daemons) EXPECT_TRUE(d->alive()) << id;
}

// Two secured daemons whose first handshake does not end within the grace (each hears the other's
// announcements, multicast, but none of its handshake messages, unicast, for `kBlocked`) rejoin
// (PeerWatch's first meetings), and meet once the link is whole. This exercises the rule, not the
// fault it is for: in CI (2026-11-29) two daemons started together never authenticated each other
// (a Fast DDS 2.9.1 fault not reproduced on demand); a blocked link is not that fault, since Fast
// DDS resends the handshake and, without the rule, the two met 0.8 s after the link was whole.
TEST_F(RejoinTest, TwoSecuredDaemonsWhoseFirstHandshakeFailedMeetByRejoining) {
  NetnsLab lab(dir_.path() / "netns", {"d1", "d2", "hc"}, kSecuredTestLease);
  const auto keystore = local::make_keystore(std::string(ISPARS_SOURCE_DIR) + "/deploy/security/make-keystore.sh",
                                             dir_.path() / "keystore", {"daemon:d1", "daemon:d2", "viewer:probe"});
  const auto identity = [&](const std::string& name) { return (keystore / "identities" / name).string(); };
  lab.deafen_unicast("d1", "d2");
  lab.deafen_unicast("d2", "d1");
  lab.enter("hc");
  std::map<std::string, std::unique_ptr<DaemonProcess>> daemons;
  for (const std::string id : {"d1", "d2"}) {
    daemons[id] = std::make_unique<DaemonProcess>(
        ISPARS_DAEMON, domain_, dir_.path() / ("data-" + id), scene_dir_, id,
        std::vector<std::string>{"--profile-file", lab.profile(id).string(), "--security", identity(id), "--metrics",
                                 lab.address(id) + ":0"},
        identity("probe"), std::vector<std::string>{}, std::chrono::seconds(60), lab.prefix(id),
        lab.profile("hc").string());
  }
  const auto discovered = [&](const std::string& id, const std::string& other) {
    return daemons[id]->log().find("(isparsd " + other + ") discovered") != std::string::npos;
  };
  ASSERT_TRUE(eventually([&] { return discovered("d1", "d2") && discovered("d2", "d1"); }, 30s,
                         "the daemons discover each other", 200ms))
      << daemons["d1"]->log() << daemons["d2"]->log();
  std::this_thread::sleep_for(kBlocked);  // the fault goes on
  lab.undeafen_unicast("d1", "d2");
  lab.undeafen_unicast("d2", "d1");
  const auto whole_at = Clock::now();
  std::map<std::string, int> ports;
  for (auto& [id, d] : daemons) ports[id] = metrics_port(d->log(), lab.address(id));
  const auto connected = [&] {
    return other_daemons_counted_on(ports["d1"], lab.address("d1")) == 1 &&
           other_daemons_counted_on(ports["d2"], lab.address("d2")) == 1;
  };
  ASSERT_TRUE(eventually(connected, kFirstMeetingBound, "the daemons meet", 200ms))
      << daemons["d1"]->log() << daemons["d2"]->log();
  const double met_s = std::chrono::duration<double>(Clock::now() - whole_at).count();
  // The positive control: the handshake did fail, and a rejoin was what met them.
  const std::string failed = "was discovered and did not authenticate within 10 s";
  EXPECT_TRUE(daemons["d1"]->log().find(failed) != std::string::npos ||
              daemons["d2"]->log().find(failed) != std::string::npos);
  std::printf("first handshake blocked %lld s: the daemons met %.1f s after the link was whole (bound %lld s)\n",
              static_cast<long long>(kBlocked.count()), met_s, static_cast<long long>(kFirstMeetingBound.count()));
  for (auto& [id, d] : daemons) EXPECT_TRUE(d->alive()) << id;
}

}  // namespace
}  // namespace ispars::test
