// RejoinSchedule over PeerWatch: a peer that came back and did not authenticate again within the
// grace makes a rejoin due, at most once per period; one that authenticates, leaves or is
// dropped again makes none; a failed rejoin is due again after the period.

#include "ispars/wire/rejoin_schedule.hpp"

#include <gtest/gtest.h>

namespace ispars::wire {
namespace {

using namespace std::chrono_literals;
using Clock = RejoinSchedule::Clock;
const Clock::time_point epoch{};

void come_back(PeerWatch& peers, const std::string& prefix, Clock::time_point at) {
  peers.discovered(prefix, "isparsd " + prefix, at);
  peers.dropped(prefix);
  peers.discovered(prefix, "isparsd " + prefix, at);
}

TEST(RejoinSchedule, AnUnhealedPeerRejoinsAfterTheGraceThenAtMostOncePerPeriod) {
  PeerWatch peers;
  RejoinSchedule schedule(30s, 5s);
  EXPECT_FALSE(schedule.poll(peers, epoch + 1s).now);
  come_back(peers, "a", epoch + 2s);
  EXPECT_FALSE(schedule.poll(peers, epoch + 6s).now);  // within the grace: it may authenticate yet
  const auto first = schedule.poll(peers, epoch + 7s);
  ASSERT_TRUE(first.now);
  EXPECT_EQ(first.now->prefix, "a");
  come_back(peers, "b", epoch + 10s);
  const auto early = schedule.poll(peers, epoch + 16s);
  EXPECT_FALSE(early.now);
  ASSERT_TRUE(early.deferred);
  EXPECT_EQ(early.since_last, 9s);
  EXPECT_FALSE(schedule.poll(peers, epoch + 17s).deferred);  // said once
  EXPECT_FALSE(schedule.poll(peers, epoch + 36s).now);       // still within 30 s of the first
  const auto due = schedule.poll(peers, epoch + 37s);
  ASSERT_TRUE(due.now);
  EXPECT_EQ(due.now->prefix, "b");
  EXPECT_FALSE(schedule.poll(peers, epoch + 90s).now);  // nothing left
}

// A cut both ways: each side dropped the other, and they authenticate afresh. No rejoin.
TEST(RejoinSchedule, APeerThatAuthenticatesLeavesOrIsDroppedAgainMakesNoRejoin) {
  PeerWatch peers;
  RejoinSchedule schedule(30s, 5s);
  come_back(peers, "a", epoch);
  peers.authenticated("a");
  come_back(peers, "b", epoch);
  peers.left("b");  // it rejoined itself
  come_back(peers, "c", epoch);
  peers.dropped("c");  // gone again
  EXPECT_FALSE(schedule.poll(peers, epoch + 60s).now);
  EXPECT_FALSE(peers.unhealed(epoch + 60s, 5s));
}

TEST(RejoinSchedule, AFailedRejoinIsDueAgainAfterThePeriod) {
  PeerWatch peers;
  RejoinSchedule schedule(30s, 5s);
  come_back(peers, "a", epoch);
  const auto first = schedule.poll(peers, epoch + 5s);
  ASSERT_TRUE(first.now);
  schedule.failed(*first.now);
  EXPECT_FALSE(schedule.poll(peers, epoch + 34s).now);
  const auto again = schedule.poll(peers, epoch + 35s);
  ASSERT_TRUE(again.now);
  EXPECT_EQ(again.now->prefix, "a");
}

// A daemon whose first handshake never ends makes one rejoin; if the new participant cannot meet
// it either (say it has no security), it is given up, not rejoined for every period.
TEST(RejoinSchedule, AFirstMeetingThatFailsTwiceIsGivenUp) {
  RejoinSchedule schedule(30s, 10s);
  PeerWatch first(PeerWatch::FirstMeetings{"isparsd a"});
  first.discovered("0b", "isparsd b", epoch);
  const auto rejoin = schedule.poll(first, epoch + 10s);
  ASSERT_TRUE(rejoin.now);
  EXPECT_TRUE(rejoin.now->first_meeting);
  EXPECT_NE(schedule.reason(*rejoin.now).find("isparsd b (0b) was discovered and did not authenticate within 10 s"),
            std::string::npos);
  PeerWatch second(PeerWatch::FirstMeetings{"isparsd a"});  // the new participant's
  second.discovered("0b", "isparsd b", epoch + 10s);
  second.discovered("0c", "isparsd c", epoch + 10s);
  const auto later = schedule.poll(second, epoch + 60s);
  ASSERT_TRUE(later.given_up);
  EXPECT_EQ(later.given_up->prefix, "0b");
  ASSERT_TRUE(later.now);  // another daemon still counts
  EXPECT_EQ(later.now->prefix, "0c");
}

}  // namespace
}  // namespace ispars::wire
