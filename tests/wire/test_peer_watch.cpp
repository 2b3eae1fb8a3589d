// PeerWatch: a peer dropped (its lease ran out) and discovered again under the same GUID is
// "unhealed" until it authenticates again, leaves or is dropped again; a new peer, or one seen
// again without being dropped, never is, unless first meetings are watched (under security) and
// it is a daemon whose first handshake never ends.

#include <gtest/gtest.h>

#include "ispars/wire/participant.hpp"

namespace ispars::wire {
namespace {

using namespace std::chrono_literals;
const PeerWatch::Clock::time_point t0{};

TEST(PeerWatch, APeerDroppedAndDiscoveredAgainIsUnhealedUntilItAuthenticates) {
  PeerWatch peers;
  peers.discovered("01.02", "isparsd a", t0);  // first seen: nothing to report
  EXPECT_FALSE(peers.unhealed(t0 + 10s, 1s));
  peers.dropped("01.02");
  EXPECT_FALSE(peers.unhealed(t0 + 10s, 1s));  // dropped, not back yet
  peers.discovered("09.09", "isparsd b", t0);  // another peer, new
  EXPECT_FALSE(peers.unhealed(t0 + 10s, 1s));
  peers.discovered("01.02", "isparsd a", t0 + 20s);
  EXPECT_FALSE(peers.unhealed(t0 + 20s, 1s));  // within the grace
  const auto back = peers.unhealed(t0 + 21s, 1s);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->prefix, "01.02");
  EXPECT_EQ(back->name, "isparsd a");
  EXPECT_TRUE(peers.take_unhealed(t0 + 21s, 1s).has_value());
  EXPECT_FALSE(peers.take_unhealed(t0 + 22s, 1s).has_value());  // once
  peers.discovered("01.02", "isparsd a", t0 + 30s);             // seen again without a drop
  EXPECT_FALSE(peers.unhealed(t0 + 40s, 1s));
  peers.dropped("01.02");
  peers.discovered("01.02", "isparsd a", t0 + 50s);
  peers.authenticated("01.02");  // healed by itself
  EXPECT_FALSE(peers.unhealed(t0 + 60s, 1s));
}

TEST(PeerWatch, APeerThatLeftOrWasDroppedAgainIsNotUnhealed) {
  PeerWatch peers;
  peers.discovered("01.02", "isparsd a", t0);
  peers.dropped("01.02");
  peers.discovered("01.02", "isparsd a", t0);
  peers.left("01.02");  // rejoined itself: its old participant is deleted
  peers.discovered("03.04", "ispars client", t0);
  peers.dropped("03.04");
  peers.discovered("03.04", "ispars client", t0);
  peers.dropped("03.04");  // dropped again before anyone looked
  EXPECT_FALSE(peers.unhealed(t0 + 60s, 1s));
}

// Under DDS Security a daemon's first handshake that never ends leaves it unhealed too; a client,
// this participant's own name, a refused peer or one authenticated (whichever callback came
// first) does not.
TEST(PeerWatch, ADaemonWhoseFirstHandshakeNeverEndsIsUnhealed) {
  PeerWatch peers(PeerWatch::FirstMeetings{"isparsd a"});
  peers.discovered("0b", "isparsd b", t0);
  peers.discovered("0c", "ispars client", t0);
  peers.discovered("0a", "isparsd a", t0);  // this daemon's other participant, during its rejoin
  peers.authenticated("0d");
  peers.discovered("0d", "isparsd d", t0);
  peers.discovered("0e", "isparsd e", t0);
  peers.refused("0e");
  peers.discovered("0f", "isparsd f", t0);
  peers.authenticated("0f");
  EXPECT_FALSE(peers.unhealed(t0 + 9s, 10s));  // within the grace
  const auto stuck = peers.take_unhealed(t0 + 10s, 10s);
  ASSERT_TRUE(stuck.has_value());
  EXPECT_EQ(stuck->prefix, "0b");
  EXPECT_TRUE(stuck->first_meeting);
  EXPECT_FALSE(peers.unhealed(t0 + 60s, 10s));
  // Without FirstMeetings (no security) a first meeting is never watched.
  PeerWatch plain;
  plain.discovered("0b", "isparsd b", t0);
  EXPECT_FALSE(plain.unhealed(t0 + 60s, 10s));
}

TEST(PeerWatch, DroppedPeersAreBounded) {
  PeerWatch peers;
  for (int i = 0; i < 5000; ++i) {
    std::string prefix(1, 'p');  // appended: GCC 12 warns falsely on "p" + std::to_string(i)
    prefix += std::to_string(i);
    peers.dropped(prefix);
  }
  peers.discovered("p4999", "isparsd x", t0);  // the newest is remembered
  EXPECT_TRUE(peers.unhealed(t0 + 10s, 1s).has_value());
}

}  // namespace
}  // namespace ispars::wire
