// The fleet's ownership rule: holders keep their scenes, rendezvous weights assign the rest
// (stored roadmaps first), and every party computing it over the same announcements agrees.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "ispars/wire/scene_owner.hpp"

namespace ispars::wire {
namespace {

msg::DaemonInfo daemon(const std::string& id, std::vector<std::string> available, std::vector<std::string> loaded = {},
                       std::vector<std::string> stored = {}) {
  msg::DaemonInfo d;
  d.server_id(id);
  for (const auto& s : available) d.available().push_back(s);
  for (const auto& s : loaded) d.loaded().push_back(s);
  for (const auto& s : stored) d.stored().push_back(s);
  return d;
}

// PREFIX + i (appended: GCC 12 warns falsely on "s" + std::to_string(i)).
std::string name(std::string prefix, int i) {
  prefix += std::to_string(i);
  return prefix;
}

TEST(SceneOwner, WeightsAreFixedAndSeparateTheTwoNames) {
  // Pinned: every daemon and client of this protocol must compute the same weights.
  EXPECT_EQ(rendezvous_weight("s0", "alpha"), rendezvous_weight("s0", "alpha"));
  EXPECT_NE(rendezvous_weight("ab", "c"), rendezvous_weight("a", "bc"));
  EXPECT_NE(rendezvous_weight("s0", "alpha"), rendezvous_weight("alpha", "s0"));
  EXPECT_NE(rendezvous_weight("s0", "alpha"), rendezvous_weight("s1", "alpha"));
}

TEST(SceneOwner, OutranksIsAStrictOrderForEveryScene) {
  for (const std::string scene : {"s0", "s1", "water_tower", "x"}) {
    for (const std::string a : {"a", "b", "c"}) {
      EXPECT_FALSE(outranks(scene, a, a));
      for (const std::string b : {"a", "b", "c"}) {
        if (a != b) {
          EXPECT_NE(outranks(scene, a, b), outranks(scene, b, a)) << scene << " " << a << " " << b;
        }
      }
    }
  }
}

TEST(SceneOwner, AssignmentSpreadsScenesOverDaemonsAndDependsOnNoOrder) {
  std::vector<msg::DaemonInfo> live;
  std::vector<std::string> scenes;
  for (int i = 0; i < 200; ++i) scenes.push_back(name("scene", i));
  for (const std::string id : {"east-1", "east-2", "west-1"}) live.push_back(daemon(id, scenes));
  std::map<std::string, int> count;
  for (const auto& s : scenes) {
    const std::string owner = owner_of(s, live);
    std::vector<msg::DaemonInfo> reversed(live.rbegin(), live.rend());
    EXPECT_EQ(owner, owner_of(s, reversed));
    ++count[owner];
  }
  ASSERT_EQ(count.size(), 3u);
  for (const auto& [id, n] : count) EXPECT_GT(n, 40) << id;  // about 67 each
}

TEST(SceneOwner, AHolderKeepsItsSceneWhateverTheWeights) {
  // Whoever the rule would pick, the daemon already holding a scene keeps it.
  for (const std::string id : {"a", "b", "c"}) {
    std::vector<msg::DaemonInfo> live;
    for (const std::string other : {"a", "b", "c"}) {
      live.push_back(daemon(other, {"s"}, other == id ? std::vector<std::string>{"s"} : std::vector<std::string>{}));
    }
    EXPECT_EQ(holder_of("s", live), id);
    EXPECT_EQ(owner_of("s", live), id);
  }
}

TEST(SceneOwner, AStoredRoadmapWinsOverAHigherWeight) {
  std::vector<msg::DaemonInfo> live{daemon("a", {"s"}), daemon("b", {"s"}), daemon("c", {"s"})};
  const std::string by_weight = assigned_daemon("s", live);
  for (auto& d : live) {
    if (d.server_id() != by_weight) {
      d.stored().push_back("s");
      EXPECT_EQ(assigned_daemon("s", live), d.server_id().to_string());
      break;
    }
  }
}

TEST(SceneOwner, OnlyDaemonsOfferingTheSceneAreAssignedIt) {
  std::vector<msg::DaemonInfo> live{daemon("a", {"other"}), daemon("b", {"s"}), daemon("c", {})};
  EXPECT_EQ(owner_of("s", live), "b");
  EXPECT_EQ(owner_of("nowhere", live), "");
  EXPECT_EQ(owner_of("s", {}), "");
}

TEST(SceneOwner, ALeavingDaemonMovesOnlyItsOwnScenes) {
  std::vector<std::string> scenes;
  for (int i = 0; i < 100; ++i) scenes.push_back(name("s", i));
  std::vector<msg::DaemonInfo> three{daemon("a", scenes), daemon("b", scenes), daemon("c", scenes)};
  std::vector<msg::DaemonInfo> two{daemon("a", scenes), daemon("b", scenes)};
  for (const auto& s : scenes) {
    if (assigned_daemon(s, three) != "c") {
      EXPECT_EQ(assigned_daemon(s, two), assigned_daemon(s, three)) << s;
    }
  }
}

TEST(SceneOwner, TwoHoldersResolveToTheHigherRankedEverywhere) {
  std::vector<msg::DaemonInfo> live{daemon("a", {"s"}, {"s"}), daemon("b", {"s"}, {"s"})};
  const std::string h = holder_of("s", live);
  EXPECT_TRUE(outranks("s", h, h == "a" ? "b" : "a"));
}

}  // namespace
}  // namespace ispars::wire
