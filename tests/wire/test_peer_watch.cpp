// PeerWatch: a peer dropped (its lease ran out) and discovered again under the same GUID is
// reported once; a new peer, or one seen again without being dropped, is not.

#include <gtest/gtest.h>

#include "ispars/wire/participant.hpp"

namespace ispars::wire {
namespace {

TEST(PeerWatch, APeerDroppedAndDiscoveredAgainIsReportedOnce) {
  PeerWatch peers;
  peers.discovered("01.02", "isparsd a");  // first seen: nothing to report
  EXPECT_FALSE(peers.take_returned().has_value());
  peers.dropped("01.02");
  EXPECT_FALSE(peers.take_returned().has_value());  // dropped, not back yet
  peers.discovered("09.09", "isparsd b");           // another peer, new
  EXPECT_FALSE(peers.take_returned().has_value());
  peers.discovered("01.02", "isparsd a");
  const auto back = peers.take_returned();
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->prefix, "01.02");
  EXPECT_EQ(back->name, "isparsd a");
  EXPECT_FALSE(peers.take_returned().has_value());  // once
  peers.discovered("01.02", "isparsd a");           // seen again without a drop in between
  EXPECT_FALSE(peers.take_returned().has_value());
}

TEST(PeerWatch, DroppedPeersAreBounded) {
  PeerWatch peers;
  for (int i = 0; i < 5000; ++i) {
    std::string prefix(1, 'p');  // appended: GCC 12 warns falsely on "p" + std::to_string(i)
    prefix += std::to_string(i);
    peers.dropped(prefix);
  }
  peers.discovered("p4999", "isparsd x");  // the newest is remembered
  EXPECT_TRUE(peers.take_returned().has_value());
}

}  // namespace
}  // namespace ispars::wire
