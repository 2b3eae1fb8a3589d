// SceneClaims over a scripted fleet: claims refused to a holder or the assigned daemon, claims
// made at the same instant on stale views, scenes given up, and takeovers after a holder left.

#include <gtest/gtest.h>

#include <mutex>
#include <optional>
#include <set>
#include <tuple>

#include "ispars/params/input_error.hpp"
#include "ispars/server/scene_claims.hpp"
#include "ispars/wire/scene_owner.hpp"
#include "wire/stored_roadmap_fixture.hpp"

namespace ispars::server {
namespace {

msg::DaemonInfo info(const std::string& id, std::vector<std::string> loaded = {}) {
  msg::DaemonInfo d;
  d.server_id(id);
  d.available().push_back("s");
  for (const auto& s : loaded) d.loaded().push_back(s);
  return d;
}

// A fleet whose other daemons the test sets; `after_announce` replaces them when this daemon
// announces (what the others did meanwhile, seen only after the claim went out).
struct ScriptedFleet {
  std::mutex mutex;
  std::vector<msg::DaemonInfo> others;
  std::optional<std::vector<msg::DaemonInfo>> after_announce;
  int announcements = 0;
  SceneClaims* claims = nullptr;
  std::string self;
  std::optional<std::tuple<std::uint64_t, std::uint64_t, std::uint64_t>> self_copy;  // generation, samples, target
  // A fake clock: the claim window's wait moves it on at once; a test moves it past a retry period.
  std::chrono::steady_clock::time_point clock{};
  std::set<std::string> taking_over;  // scenes whose takeover runs here (the daemon's TakeoverRunner)

  Fleet fleet() {
    Fleet f{[this] {
              std::lock_guard lock(mutex);
              return others;
            },
            [this] {
              msg::DaemonInfo d = info(self);
              for (const auto& s : claims->claimed()) d.loaded().push_back(s);
              if (self_copy) {
                msg::StoredRoadmap r;
                r.scene("s");
                r.generation(std::get<0>(*self_copy));
                r.samples(std::get<1>(*self_copy));
                r.target(std::get<2>(*self_copy));
                d.roadmaps().push_back(r);
              }
              return d;
            },
            [this] {
              std::lock_guard lock(mutex);
              ++announcements;
              if (after_announce) others = *std::exchange(after_announce, std::nullopt);
            }};
    f.now = [this] {
      std::lock_guard lock(mutex);
      return clock;
    };
    f.sleep = [this](std::chrono::milliseconds d) { pass(d); };
    f.taking_over = [this](const std::string& scene) {
      std::lock_guard lock(mutex);
      return taking_over.count(scene) > 0;
    };
    return f;
  }
  void pass(std::chrono::steady_clock::duration d) {
    std::lock_guard lock(mutex);
    clock += d;
  }
};

// Two daemon ids: `high` outranks `low` for scene "s".
struct Ranked {
  std::string high = "a", low = "b";
  Ranked() {
    if (!wire::outranks("s", high, low)) std::swap(high, low);
  }
};

struct Claims {
  ScriptedFleet fleet;
  std::unique_ptr<SceneClaims> claims;
  explicit Claims(const std::string& self) {
    fleet.self = self;
    claims = std::make_unique<SceneClaims>(self, fleet.fleet());
    fleet.claims = claims.get();
  }
};

std::string claim_error(SceneClaims& claims, const std::string& scene) {
  try {
    claims.claim(scene);
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneClaims, ASceneHeldElsewhereIsRefusedNamingItsHolder) {
  const Ranked r;
  Claims c(r.high);
  c.fleet.others = {info(r.low, {"s"})};  // the lower-ranked daemon holds it: it keeps it
  EXPECT_NE(claim_error(*c.claims, "s").find("scene 's' is owned by daemon " + r.low), std::string::npos);
  EXPECT_TRUE(c.claims->claimed().empty());
  EXPECT_EQ(c.fleet.announcements, 0);
}

TEST(SceneClaims, ASceneAssignedElsewhereIsRefusedNamingTheRule) {
  const Ranked r;
  Claims c(r.low);
  c.fleet.others = {info(r.high)};
  const std::string error = claim_error(*c.claims, "s");
  EXPECT_NE(error.find("belongs to daemon " + r.high + " by the fleet's rule"), std::string::npos) << error;
  EXPECT_TRUE(c.claims->claimed().empty());
}

TEST(SceneClaims, AnAssignedSceneIsClaimedAnnouncedAndReleased) {
  const Ranked r;
  Claims c(r.high);
  c.fleet.others = {info(r.low)};
  EXPECT_EQ(claim_error(*c.claims, "s"), "");
  EXPECT_EQ(c.claims->claimed(), std::vector<std::string>{"s"});
  EXPECT_EQ(c.fleet.announcements, 1);
  EXPECT_EQ(claim_error(*c.claims, "s"), "");  // already claimed: no second announcement
  EXPECT_EQ(c.fleet.announcements, 1);
  c.claims->release("s");
  EXPECT_TRUE(c.claims->claimed().empty());
}

TEST(SceneClaims, OfTwoClaimsAtTheSameInstantTheOutrankedOneWithdraws) {
  const Ranked r;
  // The lower-ranked daemon saw no other daemon when it claimed; during its claim window the
  // higher-ranked one turns up holding the scene.
  Claims low(r.low);
  low.fleet.after_announce = std::vector<msg::DaemonInfo>{info(r.high, {"s"})};
  const std::string error = claim_error(*low.claims, "s");
  EXPECT_NE(error.find("daemon " + r.high + " claimed scene 's' at the same moment"), std::string::npos) << error;
  EXPECT_TRUE(low.claims->claimed().empty());
  EXPECT_EQ(low.fleet.announcements, 2);  // the claim, then its withdrawal
  // The higher-ranked daemon, in the mirror situation, keeps its claim.
  Claims high(r.high);
  high.fleet.after_announce = std::vector<msg::DaemonInfo>{info(r.low, {"s"})};
  EXPECT_EQ(claim_error(*high.claims, "s"), "");
  EXPECT_TRUE(high.claims->contested().empty());
}

TEST(SceneClaims, AClaimSeenOnlyAfterTheWindowIsContestedAndGivenUpByTheOutranked) {
  const Ranked r;
  Claims low(r.low);
  EXPECT_EQ(claim_error(*low.claims, "s"), "");  // alone on its view
  low.fleet.others = {info(r.high, {"s"})};      // a late announcement: both hold it
  const auto contested = low.claims->contested();
  ASSERT_EQ(contested.size(), 1u);
  EXPECT_EQ(contested[0].scene, "s");
  EXPECT_EQ(contested[0].winner, r.high);
  EXPECT_TRUE(contested[0].winner_holds);
  EXPECT_NE(contested[0].why.find("settled by rendezvous weight"), std::string::npos) << contested[0].why;
  Claims high(r.high);
  EXPECT_EQ(claim_error(*high.claims, "s"), "");
  high.fleet.others = {info(r.low, {"s"})};
  EXPECT_TRUE(high.claims->contested().empty());
}

msg::SceneStatus status(const std::string& server, msg::SceneState state, const std::string& method);

// `d` with a copy of "s" announced (handed to `yielded_to`, with `target` accepted).
msg::DaemonInfo with_copy(msg::DaemonInfo d, std::uint64_t generation, std::uint64_t samples,
                          const std::string& yielded_to = "", std::uint64_t target = 0) {
  return test::add_copy(d, generation, samples, target, yielded_to);
}

// The holder of a stale copy gives the scene up to a daemon that stores a fresher one, whatever
// the weights say, and names why.
TEST(SceneClaims, AHolderGivesUpToAFresherStoredCopy) {
  const Ranked r;
  Claims c(r.high);
  ASSERT_EQ(claim_error(*c.claims, "s"), "");
  c.fleet.others = {with_copy(info(r.low), 7, 20000)};  // this daemon's own copy: none
  auto contested = c.claims->contested();
  ASSERT_EQ(contested.size(), 1u);
  EXPECT_EQ(contested[0].winner, r.low);
  EXPECT_FALSE(contested[0].winner_holds);
  EXPECT_NE(contested[0].why.find("its copy is fresher (generation 7, 20000 samples"), std::string::npos)
      << contested[0].why;
  // A copy of an older generation, however large, does not make it give the scene up.
  c.fleet.others = {with_copy(info(r.low), 6, 90000)};
  c.fleet.self_copy = std::make_tuple(7, 1000, 1000);
  EXPECT_TRUE(c.claims->contested().empty());
}

// The winner of a handover takes the scene once the loser released it, with the samples the
// loser had accepted; a daemon the handover does not name does nothing.
TEST(SceneClaims, AHandedOverSceneIsTakenByTheDaemonItWasHandedTo) {
  Claims winner("w");
  Claims bystander("b");
  const msg::DaemonInfo loser = with_copy(info("l"), 7, 12000, "w", 30000);
  winner.fleet.others = {info("l", {"s"})};
  bystander.fleet.others = {info("l", {"s"})};
  EXPECT_TRUE(winner.claims->orphans().empty());  // still held
  winner.claims->observe(status("l", msg::SCENE_BUILDING, "ispars"));
  winner.fleet.others = {loser, info("b")};
  bystander.fleet.others = {loser, info("w")};
  const auto orphans = winner.claims->orphans();
  ASSERT_EQ(orphans.size(), 1u);
  EXPECT_TRUE(orphans[0].handed_over);
  EXPECT_EQ(orphans[0].former_owner, "l");
  EXPECT_EQ(orphans[0].accepted, 30000u);
  ASSERT_TRUE(orphans[0].last_status.has_value());
  EXPECT_TRUE(winner.claims->orphans().empty());  // not again before the retry period
  EXPECT_TRUE(bystander.claims->orphans().empty());
}

// Each status a later one than the one before (status_seq increases), as one daemon run issues them.
msg::SceneStatus status(const std::string& server, msg::SceneState state, const std::string& method) {
  static std::uint64_t seq = 0;
  msg::SceneStatus s;
  s.scene("s");
  s.server_id(server);
  s.status_seq(++seq);
  s.state(state);
  s.method(method);
  s.seed(7);
  s.samples_done(1234);
  return s;
}

TEST(SceneClaims, AHolderThatLeavesIsTakenOverOnceWithItsLastRecipe) {
  const Ranked r;
  Claims c(r.low);
  const std::string gone = "gone";
  c.fleet.others = {info(gone, {"s"}), info(r.high)};
  EXPECT_TRUE(c.claims->orphans().empty());  // held by a live daemon
  c.claims->observe(status(gone, msg::SCENE_IDLE, "ispars"));
  c.claims->observe(status(gone, msg::SCENE_UNLOADED, ""));  // a stopping daemon's last word
  c.fleet.others = {info(r.high)};                           // `gone` left
  EXPECT_TRUE(c.claims->orphans().empty());                  // the rule gives it to r.high, not here
  c.fleet.others = {};                                       // r.high left too, before taking it
  const auto orphans = c.claims->orphans();
  ASSERT_EQ(orphans.size(), 1u);
  EXPECT_EQ(orphans[0].scene, "s");
  EXPECT_EQ(orphans[0].former_owner, gone);
  ASSERT_TRUE(orphans[0].last_status.has_value());
  EXPECT_EQ(orphans[0].last_status->method(), "ispars");
  EXPECT_EQ(orphans[0].last_status->samples_done(), 1234u);
  EXPECT_TRUE(c.claims->orphans().empty());  // reported once
}

// DDS orders samples per writer only: a rejoining daemon's old participant's last status can
// arrive after its new participant's newer one (t60 in docs/results/fleet.md: a taker then
// rebuilt without an acknowledged task). The older one is ignored; a new run (a restart, its
// status_seq starting again) replaces what the old run published.
TEST(SceneClaims, ALateOlderStatusHidesNoNewerOneOfTheSameRun) {
  Claims c("me");
  msg::DaemonInfo holder = info("holder", {"s"});
  const auto leaves = [&](const std::vector<msg::SceneStatus>& statuses) {
    c.fleet.others = {holder};
    (void)c.claims->orphans();
    for (const auto& st : statuses) c.claims->observe(st);
    c.fleet.others = {};
    auto orphans = c.claims->orphans();
    EXPECT_EQ(claim_error(*c.claims, "s"), "");  // taken over; then released again
    c.claims->release("s");
    return orphans;
  };
  holder.joined_ms(1000);
  const msg::SceneStatus older = status("holder", msg::SCENE_IDLE, "ispars");
  msg::SceneStatus newer = status("holder", msg::SCENE_IDLE, "ispars");
  newer.task_events(1);
  auto orphans = leaves({newer, older});
  ASSERT_EQ(orphans.size(), 1u);
  ASSERT_TRUE(orphans[0].last_status.has_value());
  EXPECT_EQ(orphans[0].last_status->task_events(), 1u);
  holder.joined_ms(2000);  // restarted: its statuses count from 1 again
  msg::SceneStatus restarted = status("holder", msg::SCENE_IDLE, "spars");
  restarted.status_seq(1);
  msg::SceneStatus later = restarted;
  later.status_seq(2);
  later.task_events(5);
  orphans = leaves({later, restarted});  // the new run's, late again within it
  ASSERT_EQ(orphans.size(), 1u);
  ASSERT_TRUE(orphans[0].last_status.has_value());
  EXPECT_EQ(orphans[0].last_status->task_events(), 5u);
  EXPECT_EQ(orphans[0].last_status->method(), "spars");
}

// A daemon starting beside a holder is refused the scene; the holder stops before the fleet
// thread ever looked: the refused claim alone is enough to take the scene over.
TEST(SceneClaims, AHolderThatRefusedAClaimAndLeftIsTakenOver) {
  Claims c("me");
  c.fleet.others = {info("holder", {"s"})};
  EXPECT_NE(claim_error(*c.claims, "s").find("owned by daemon holder"), std::string::npos);
  c.claims->observe(status("holder", msg::SCENE_IDLE, "ispars"));
  c.fleet.others = {};
  const auto orphans = c.claims->orphans();
  ASSERT_EQ(orphans.size(), 1u);
  EXPECT_EQ(orphans[0].former_owner, "holder");
  EXPECT_FALSE(orphans[0].handed_over);
}

// A takeover that failed (the load or build threw) is reported again after the retry period,
// until the scene is held here.
TEST(SceneClaims, AFailedTakeoverIsReportedAgainUntilTheSceneIsHeld) {
  Claims c("me");
  c.fleet.others = {info("gone", {"s"})};
  (void)c.claims->orphans();
  c.fleet.others = {};
  ASSERT_EQ(c.claims->orphans().size(), 1u);
  EXPECT_TRUE(c.claims->orphans().empty());
  c.fleet.pass(SceneClaims::kRetryPeriod - std::chrono::milliseconds(1));
  EXPECT_TRUE(c.claims->orphans().empty());  // not before the retry period
  c.fleet.pass(std::chrono::milliseconds(1));
  const auto again = c.claims->orphans();
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].former_owner, "gone");
  EXPECT_EQ(claim_error(*c.claims, "s"), "");  // taken over now
  c.fleet.pass(SceneClaims::retry_delay(4));
  EXPECT_TRUE(c.claims->orphans().empty());
}

// A takeover runs beside the fleet thread: its claim seen by the next pass does not end the
// scene's pending takeover (a failure then, its claim released, is tried again after the retry
// period; before, the claim erased it and the failure was never retried). Its success does.
TEST(SceneClaims, ATakeoverRunningBesideTheFleetThreadStaysPendingUntilItEnds) {
  for (const bool fails : {true, false}) {
    Claims c("me");
    c.fleet.others = {info("gone", {"s"})};
    (void)c.claims->orphans();
    c.fleet.others = {};
    ASSERT_EQ(c.claims->orphans().size(), 1u);
    c.fleet.taking_over = {"s"};  // started
    EXPECT_EQ(claim_error(*c.claims, "s"), "");
    EXPECT_TRUE(c.claims->orphans().empty());  // the next pass, while it runs
    if (fails) c.claims->release("s");
    EXPECT_EQ(c.claims->takeover_retry_in("s"), SceneClaims::kRetryPeriod);
    c.fleet.taking_over.clear();  // ended
    (void)c.claims->orphans();
    c.fleet.pass(SceneClaims::kRetryPeriod);
    EXPECT_EQ(c.claims->orphans().size(), fails ? 1u : 0u) << (fails ? "failed" : "succeeded");
  }
}

TEST(SceneClaims, ASceneReleasedOnPurposeIsNoOrphan) {
  Claims c("me");
  c.fleet.others = {info("other", {"s"})};
  EXPECT_TRUE(c.claims->orphans().empty());
  c.fleet.others = {info("other")};  // still live, unloaded it
  EXPECT_TRUE(c.claims->orphans().empty());
  c.fleet.others = {};  // then left: it held nothing any more
  EXPECT_TRUE(c.claims->orphans().empty());
}

TEST(SceneClaims, ADroppedRoadmapIsNotRebuiltByTheTaker) {
  Claims c("me");
  c.fleet.others = {info("other", {"s"})};
  (void)c.claims->orphans();
  c.claims->observe(status("other", msg::SCENE_IDLE, "ispars"));
  c.claims->observe(status("other", msg::SCENE_EMPTY, ""));  // dropped
  c.fleet.others = {};
  const auto orphans = c.claims->orphans();
  ASSERT_EQ(orphans.size(), 1u);
  ASSERT_TRUE(orphans[0].last_status.has_value());
  EXPECT_EQ(orphans[0].last_status->method(), "");
}

// The held-empty scene with a third daemon: the daemon the rule named first ("first"
// outranks this one) holds the scene a moment, fails, releases it and declines it. The former
// owner's orphan, with its recipe, comes here; a third daemon's recipe-less status does not hide
// it. A daemon that releases the scene without declining it released it on purpose: no orphan.
TEST(SceneClaims, ATakeoverThatFailsElsewhereComesHereWithTheFormerOwnersRecipe) {
  for (const bool declined : {true, false}) {
    const Ranked r;
    Claims c(r.low);
    msg::DaemonInfo gone = info("gone", {"s"});
    test::add_copy(gone, 3, 1234);
    c.fleet.others = {gone, info(r.high)};
    EXPECT_TRUE(c.claims->orphans().empty());
    c.claims->observe(status("gone", msg::SCENE_IDLE, "ispars"));
    c.fleet.others = {info(r.high)};  // gone left: the rule names r.high
    EXPECT_TRUE(c.claims->orphans().empty());
    c.fleet.others = {info(r.high, {"s"})};  // r.high claims it, fails
    c.claims->observe(status(r.high, msg::SCENE_FAILED, ""));
    EXPECT_TRUE(c.claims->orphans().empty());
    msg::DaemonInfo first = info(r.high);
    if (declined) first.declined().push_back("s");
    c.fleet.others = {first};
    const auto orphans = c.claims->orphans();
    if (!declined) {
      EXPECT_TRUE(orphans.empty()) << "released on purpose: nothing to take over";
      continue;
    }
    ASSERT_EQ(orphans.size(), 1u);
    EXPECT_EQ(orphans[0].former_owner, "gone");
    EXPECT_EQ(orphans[0].accepted, 1234u);
    ASSERT_TRUE(orphans[0].last_status.has_value());
    EXPECT_EQ(orphans[0].last_status->method(), "ispars");
    EXPECT_TRUE(c.claims->orphans().empty());  // not again before the retry period
  }
}

// Once some daemon serves a copy as fresh as the former owner's, the orphan is forgotten: a
// later release by that daemon is not a takeover of the former owner's work.
TEST(SceneClaims, AnOrphanServedAgainElsewhereIsForgotten) {
  const Ranked r;
  Claims c(r.low);
  msg::DaemonInfo gone = info("gone", {"s"});
  test::add_copy(gone, 3, 1234);
  c.fleet.others = {gone, info(r.high)};
  (void)c.claims->orphans();
  c.fleet.others = {info(r.high)};
  EXPECT_TRUE(c.claims->orphans().empty());
  msg::DaemonInfo holder = info(r.high, {"s"});
  test::add_copy(holder, 3, 1000, 1234);  // rebuilding: not yet as fresh
  c.fleet.others = {holder};
  EXPECT_TRUE(c.claims->orphans().empty());
  msg::DaemonInfo served = info(r.high, {"s"});
  test::add_copy(served, 3, 1234);
  c.fleet.others = {served};
  EXPECT_TRUE(c.claims->orphans().empty());
  msg::DaemonInfo declining = info(r.high);
  declining.declined().push_back("s");
  c.fleet.others = {declining};
  EXPECT_TRUE(c.claims->orphans().empty()) << "the former owner's work was served again";
}

}  // namespace
}  // namespace ispars::server
