// LatestSamples: the latest sample per instance, gone with its writer, and back with it when the
// same writer is matched again (a lease that expired while the writer was alive).

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ispars.h"
#include "ispars/wire/daemon_trust.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/latest_samples.hpp"

namespace ispars::wire {
namespace {

namespace rtps = eprosima::fastrtps::rtps;
namespace fdds = eprosima::fastdds::dds;

msg::DaemonInfo daemon(const std::string& id, std::uint16_t protocol = 1) {
  msg::DaemonInfo d;
  d.server_id(id);
  d.protocol(protocol);
  return d;
}

// A writer of participant `n`: its GUID's prefix is what identity_of reads.
rtps::GUID_t writer_of(std::uint8_t n) {
  rtps::GUID_t guid;
  guid.guidPrefix.value[0] = 1;
  guid.guidPrefix.value[11] = n;
  guid.entityId.value[3] = 2;
  return guid;
}

rtps::InstanceHandle_t handle_of(const rtps::GUID_t& guid) {
  rtps::InstanceHandle_t h;
  h = guid;
  return h;
}

rtps::InstanceHandle_t instance(std::uint8_t key) {
  rtps::InstanceHandle_t h;
  h.value[0] = key;
  return h;
}

fdds::SubscriptionMatchedStatus matched(const rtps::GUID_t& writer, int change) {
  fdds::SubscriptionMatchedStatus s;
  s.current_count_change = change;
  s.last_publication_handle = handle_of(writer);
  return s;
}

struct Daemons {
  std::vector<std::string> changes;
  LatestSamples<msg::DaemonInfo> latest{
      [](const msg::DaemonInfo& d) { return d.server_id().to_string(); },
      [this](const msg::DaemonInfo& d) { changes.push_back(d.server_id().to_string()); }};
  void write(const rtps::GUID_t& writer, const msg::DaemonInfo& d, std::uint8_t key) {
    latest.receive(d, true, identity_of(writer.guidPrefix), instance(key));
  }
};

TEST(LatestSamples, AWriterThatLeavesTakesItsInstancesAndBringsThemBackWhenMatchedAgain) {
  Daemons d;
  d.write(writer_of(1), daemon("a", 7), 1);
  d.write(writer_of(2), daemon("b"), 2);
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), -1));  // its lease expired here
  EXPECT_FALSE(d.latest.get("a"));
  ASSERT_TRUE(d.latest.get("b"));
  // Matched again: Fast DDS does not deliver the samples this reader already took.
  d.changes.clear();
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), +1));
  ASSERT_TRUE(d.latest.get("a"));
  EXPECT_EQ(d.latest.get("a")->protocol(), 7u);
  EXPECT_EQ(d.latest.sender("a"), identity_of(writer_of(1).guidPrefix));
  EXPECT_EQ(d.changes, std::vector<std::string>{"a"});
  // Restored with its instance: the end of that instance ends it again.
  d.latest.receive(msg::DaemonInfo{}, false, "", instance(1));
  EXPECT_FALSE(d.latest.get("a"));
}

TEST(LatestSamples, AReturningWriterDoesNotOverwriteWhatAnotherWroteMeanwhile) {
  Daemons d;
  d.write(writer_of(1), daemon("a", 1), 1);
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), -1));
  d.write(writer_of(3), daemon("a", 2), 1);  // a restarted daemon with the same id
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), +1));
  ASSERT_TRUE(d.latest.get("a"));
  EXPECT_EQ(d.latest.get("a")->protocol(), 2u);
  EXPECT_EQ(d.latest.sender("a"), identity_of(writer_of(3).guidPrefix));
}

TEST(LatestSamples, ANewWriterRestoresNothingAndWritersThatNeverReturnAreForgottenInTheEnd) {
  Daemons d;
  d.write(writer_of(1), daemon("a"), 1);
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), -1));
  d.latest.on_subscription_matched(nullptr, matched(writer_of(9), +1));  // someone else
  EXPECT_FALSE(d.latest.get("a"));
  // 64 more writers leave: the first one's instances are no longer kept.
  for (std::uint8_t n = 10; n < 10 + 64; ++n) {
    std::string id = std::to_string(n);
    id.insert(id.begin(), 'd');
    d.write(writer_of(n), daemon(id), n);
    d.latest.on_subscription_matched(nullptr, matched(writer_of(n), -1));
  }
  EXPECT_TRUE(d.latest.all().empty());
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), +1));
  EXPECT_FALSE(d.latest.get("a"));
  d.latest.on_subscription_matched(nullptr, matched(writer_of(73), +1));  // the latest to leave
  EXPECT_TRUE(d.latest.get("d73"));
}

// A rejoining daemon announces itself from two participants for a while: the old one's last
// announcement can arrive after the new one's. Statuses of either count until it leaves (the
// daemon trust rule); a status of the new one was refused before, and lost when a later status
// replaced it among the held ones (t60 in docs/results/fleet.md).
TEST(LatestSamples, EveryLiveWriterOfAnInstanceIsTrustedForItUntilItLeaves) {
  Daemons d;
  const std::string old_one = identity_of(writer_of(1).guidPrefix), new_one = identity_of(writer_of(2).guidPrefix);
  d.write(writer_of(2), daemon("a"), 1);
  d.write(writer_of(1), daemon("a"), 1);  // late
  EXPECT_EQ(d.latest.sender("a"), old_one);
  EXPECT_TRUE(d.latest.written_by("a", old_one));
  EXPECT_TRUE(d.latest.written_by("a", new_one));
  EXPECT_FALSE(d.latest.written_by("a", identity_of(writer_of(3).guidPrefix)));

  std::vector<std::uint64_t> seen;
  LatestSamples<msg::SceneStatus> statuses([](const msg::SceneStatus& s) { return s.scene().to_string(); },
                                           [&](const msg::SceneStatus& s) { seen.push_back(s.status_seq()); },
                                           statuses_from_their_daemon(d.latest));
  msg::SceneStatus st;
  st.scene("s");
  st.server_id("a");
  st.status_seq(7);
  statuses.receive(st, true, new_one, instance(9));
  EXPECT_EQ(seen, std::vector<std::uint64_t>{7});
  st.status_seq(8);
  statuses.receive(st, true, identity_of(writer_of(3).guidPrefix), instance(9));  // announces nothing
  EXPECT_EQ(seen, std::vector<std::uint64_t>{7});

  d.latest.on_subscription_matched(nullptr, matched(writer_of(2), -1));  // the new one left
  EXPECT_FALSE(d.latest.written_by("a", new_one));
  EXPECT_TRUE(d.latest.written_by("a", old_one));
  d.latest.on_subscription_matched(nullptr, matched(writer_of(1), -1));
  EXPECT_FALSE(d.latest.written_by("a", old_one));
  EXPECT_FALSE(d.latest.get("a"));
}

}  // namespace
}  // namespace ispars::wire
