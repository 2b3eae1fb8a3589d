// FleetListing: what a daemon announces besides the scenes it holds. Scene files and stored
// roadmaps as rescanned, a handover announced with the copy until the scene is held again, and
// the notes the scenes list shows.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "ispars/server/fleet_listing.hpp"
#include "support/test_support.hpp"

namespace ispars::server {
namespace {

template <class Sequence>
std::vector<std::string> as_strings(const Sequence& seq) {
  std::vector<std::string> out;
  for (const auto& s : seq) out.push_back(s.to_string());
  return out;
}

service::ServedRoadmap served(const std::string& scene, std::uint64_t samples, bool held) {
  service::ServedRoadmap r;
  r.scene = scene;
  r.generation = 7;
  r.samples = samples;
  r.target = samples;
  r.held = held;
  return r;
}

TEST(FleetListing, ASceneFileAddedOrRemovedChangesTheListingOnce) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "scenes");
  FleetListing listing(dir.path() / "scenes", dir.path() / "data");
  EXPECT_FALSE(listing.refresh(std::nullopt)) << "nothing there, nothing changed";
  dir.write("scenes/tower.yaml", "procedural: {kind: tank_tower, seed: 1}\n");
  EXPECT_TRUE(listing.refresh(std::nullopt));
  EXPECT_FALSE(listing.refresh(std::nullopt)) << "rescanned, unchanged";
  msg::DaemonInfo info;
  listing.describe(info, {});
  EXPECT_EQ(as_strings(info.available()), std::vector<std::string>{"tower"});
  std::filesystem::remove(dir.path() / "scenes" / "tower.yaml");
  EXPECT_TRUE(listing.refresh(std::nullopt));
  msg::DaemonInfo after;
  listing.describe(after, {});
  EXPECT_TRUE(after.available().empty());
}

TEST(FleetListing, AHandedOverSceneNamesItsWinnerUntilItIsHeldAgain) {
  test::TempDir dir;
  FleetListing listing(dir.path() / "scenes", dir.path() / "data");
  listing.hand_over("s0", {"d2", 5000, 3}, "handed over to daemon d2");
  msg::DaemonInfo info;
  service::ServedRoadmap stored = served("s0", 3000, false);
  stored.task_events = 2;  // a third, acknowledged and queued, was cancelled by the handover
  listing.describe(info, {stored});
  ASSERT_EQ(info.roadmaps().size(), 1u);
  EXPECT_EQ(info.roadmaps()[0].yielded_to(), "d2");
  EXPECT_EQ(info.roadmaps()[0].target(), 5000u) << "the samples accepted here go with the scene";
  EXPECT_EQ(info.roadmaps()[0].task_events(), 3u) << "so does the task addition accepted here";
  EXPECT_EQ(listing.handed_over(), (std::vector<std::pair<std::string, std::string>>{{"s0", "d2"}}));
  EXPECT_EQ(listing.note("s0"), "handed over to daemon d2");
  // Held here (loaded again): announced as this daemon's own copy.
  msg::DaemonInfo held;
  listing.describe(held, {served("s0", 3000, true)});
  EXPECT_EQ(held.roadmaps()[0].yielded_to(), "");
  listing.held_again("s0");
  msg::DaemonInfo again;
  listing.describe(again, {served("s0", 3000, false)});
  EXPECT_EQ(again.roadmaps()[0].yielded_to(), "");
  EXPECT_EQ(again.roadmaps()[0].target(), 3000u);
  EXPECT_TRUE(listing.handed_over().empty());
}

TEST(FleetListing, NotesAreKeptPerScene) {
  test::TempDir dir;
  FleetListing listing(dir.path() / "scenes", dir.path() / "data");
  EXPECT_EQ(listing.note("s0"), "");
  listing.set_note("s0", "taken over from d1");
  listing.set_note("s1", "set aside");
  EXPECT_EQ(listing.note("s0"), "taken over from d1");
  EXPECT_EQ(listing.note("s1"), "set aside");
}

}  // namespace
}  // namespace ispars::server
