// The fleet's ownership rule: the freshest copy wins (the later generation, then the more
// samples), a holder keeps its scene against equally fresh copies, rendezvous weights break the
// remaining ties, and every party computing it over the same announcements agrees.

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "ispars/wire/scene_owner.hpp"
#include "wire/stored_roadmap_fixture.hpp"

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

msg::DaemonInfo& with_copy(msg::DaemonInfo& d, std::uint64_t generation, std::uint64_t samples,
                           std::uint64_t target = 0, const std::string& yielded_to = "") {
  return test::add_copy(d, generation, samples, target, yielded_to);
}

TEST(SceneOwner, ACopyWinsOverAHigherWeight) {
  std::vector<msg::DaemonInfo> live{daemon("a", {"s"}), daemon("b", {"s"}), daemon("c", {"s"})};
  const std::string by_weight = assigned_daemon("s", live);
  for (auto& d : live) {
    if (d.server_id() != by_weight) {
      with_copy(d, 5, 100);
      EXPECT_EQ(assigned_daemon("s", live), d.server_id().to_string());
      break;
    }
  }
}

// The a/b sequence: the daemon holding a stale copy is outweighed by one that stores a
// fresher copy of the same roadmap; clients still address the holder until it hands it over.
TEST(SceneOwner, AFresherStoredCopyOutweighsTheHolder) {
  msg::DaemonInfo o = daemon("o", {"s"}, {"s"});
  msg::DaemonInfo p = daemon("p", {"s"});
  with_copy(o, 7, 10000);
  with_copy(p, 7, 20000);
  const std::vector<msg::DaemonInfo> live{o, p};
  EXPECT_EQ(holder_of("s", live), "o");
  EXPECT_EQ(owner_of("s", live), "o");
  EXPECT_EQ(assigned_daemon("s", live), "p");
  EXPECT_EQ(claim_freshness(p, "s", live), (Freshness{7, 20000}));
}

TEST(SceneOwner, TheLaterGenerationWinsOverMoreSamples) {
  msg::DaemonInfo a = daemon("a", {"s"}, {"s"});
  msg::DaemonInfo b = daemon("b", {"s"}, {"s"});
  with_copy(a, 7, 30000);
  with_copy(b, 8, 100);
  const std::vector<msg::DaemonInfo> live{a, b};
  EXPECT_EQ(holder_of("s", live), "b");
  EXPECT_EQ(assigned_daemon("s", live), "b");
}

// A task added or removed is a commit of no sample: of two copies of one lineage at the same
// samples, the one with more task events is the fresher, and the holder without them hands over.
TEST(SceneOwner, MoreTaskEventsWinAtEqualSamples) {
  msg::DaemonInfo holder = daemon("h", {"s"}, {"s"});
  msg::DaemonInfo store = daemon("k", {"s"});
  with_copy(holder, 7, 5000);
  with_copy(store, 7, 5000);
  store.roadmaps()[0].task_events(2);
  const std::vector<msg::DaemonInfo> live{holder, store};
  EXPECT_EQ(claim_freshness(store, "s", live), (Freshness{7, 5000, 2}));
  EXPECT_EQ(assigned_daemon("s", live), "k");
  // More samples still win over more task events.
  holder.roadmaps()[0].samples(5001);
  holder.roadmaps()[0].target(5001);
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{holder, store}), "h");
}

// A daemon whose takeover failed declines the scene for a while: the rule names the next one,
// even one with no copy; a holder never declines; when all decline, the usual key decides.
TEST(SceneOwner, ADecliningDaemonIsNamedOnlyWhenEveryOtherDeclinesToo) {
  msg::DaemonInfo b = daemon("b", {"s"});
  msg::DaemonInfo c = daemon("c", {"s"});
  with_copy(b, 7, 5000);  // fresher than c, which has no copy
  const std::vector<msg::DaemonInfo> both{b, c};
  EXPECT_EQ(assigned_daemon("s", both), "b");
  b.declined().push_back("s");
  EXPECT_TRUE(declines(b, "s"));
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{b, c}), "c");
  c.declined().push_back("s");
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{b, c}), "b");
  msg::DaemonInfo holder = daemon("h", {"s"}, {"s"});
  holder.declined().push_back("s");
  EXPECT_FALSE(declines(holder, "s")) << "a holder serves the scene: it declines nothing";
}

TEST(SceneOwner, AHolderCountsTheSamplesItAccepted) {
  msg::DaemonInfo holder = daemon("h", {"s"}, {"s"});
  msg::DaemonInfo store = daemon("k", {"s"});
  with_copy(holder, 7, 5000, 30000);  // extending to 30,000
  with_copy(store, 7, 20000);
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{holder, store}), "h");
  // A stored copy's target counts for nothing: only a holder builds towards it.
  msg::DaemonInfo idle = daemon("h", {"s"});
  with_copy(idle, 7, 5000, 30000);
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{idle, store}), "k");
}

TEST(SceneOwner, ACopyHandedToALiveDaemonWeighsNothingUntilThatDaemonLeaves) {
  msg::DaemonInfo loser = daemon("l", {"s"});
  msg::DaemonInfo winner = daemon("w", {"s"});
  msg::DaemonInfo third = daemon("t", {"s"});
  with_copy(loser, 7, 20500, 0, "w");
  with_copy(winner, 7, 20000);
  with_copy(third, 7, 1000);
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{loser, winner, third}), "w");
  EXPECT_EQ(claim_freshness(loser, "s", std::vector<msg::DaemonInfo>{loser, winner}), Freshness{});
  // The winner left before holding it: the loser's copy counts again.
  EXPECT_EQ(assigned_daemon("s", std::vector<msg::DaemonInfo>{loser, third}), "l");
}

TEST(SceneOwner, EqualCopiesGoToTheHolderThenByWeight) {
  for (const std::string id : {"a", "b", "c"}) {
    std::vector<msg::DaemonInfo> live;
    for (const std::string other : {"a", "b", "c"}) {
      live.push_back(daemon(other, {"s"}, other == id ? std::vector<std::string>{"s"} : std::vector<std::string>{}));
      with_copy(live.back(), 7, 1000);
    }
    EXPECT_EQ(assigned_daemon("s", live), id);
  }
  std::vector<msg::DaemonInfo> none{daemon("a", {"s"}), daemon("b", {"s"})};
  with_copy(none[0], 7, 1000);
  with_copy(none[1], 7, 1000);
  EXPECT_TRUE(outranks("s", assigned_daemon("s", none), assigned_daemon("s", none) == "a" ? "b" : "a"));
}

// Every party must name the same owner whatever order its announcements came in: the key is a
// total order (checked on random fleets against every rotation of the list).
TEST(SceneOwner, TheOwnerDependsOnNoOrderOnRandomFleets) {
  std::uint64_t x = 12345;
  const auto next = [&] { return x = x * 6364136223846793005ULL + 1442695040888963407ULL, x >> 33; };
  for (int round = 0; round < 500; ++round) {
    std::vector<msg::DaemonInfo> live;
    for (int i = 0; i < 5; ++i) {
      const bool holds = next() % 3 == 0;
      live.push_back(daemon(name("d", i), {"s"}, holds ? std::vector<std::string>{"s"} : std::vector<std::string>{}));
      if (next() % 4 != 0) with_copy(live.back(), 1 + next() % 3, 1000 * (next() % 4), 1000 * (next() % 5));
      if (!live.back().roadmaps().empty() && next() % 5 == 0) {
        live.back().roadmaps().back().yielded_to(name("d", static_cast<int>(next() % 6)));
      }
    }
    const std::string owner = assigned_daemon("s", live);
    const std::string holder = holder_of("s", live);
    for (std::size_t k = 1; k < live.size(); ++k) {
      std::vector<msg::DaemonInfo> rotated(live.begin() + static_cast<std::ptrdiff_t>(k), live.end());
      rotated.insert(rotated.end(), live.begin(), live.begin() + static_cast<std::ptrdiff_t>(k));
      ASSERT_EQ(assigned_daemon("s", rotated), owner) << "round " << round;
      ASSERT_EQ(holder_of("s", rotated), holder) << "round " << round;
    }
    const auto won = std::find_if(live.begin(), live.end(), [&](const auto& d) { return d.server_id() == owner; });
    ASSERT_NE(won, live.end());
    for (const auto& d : live) EXPECT_FALSE(outweighs("s", d, *won, live)) << "round " << round;  // nobody outweighs it
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
