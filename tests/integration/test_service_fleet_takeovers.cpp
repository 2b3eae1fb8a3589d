// Takeovers beside the fleet thread: the scenes of a holder that left are taken over at once, not
// one after another (each takeover reads a scene file, opens a store and waits a claim window),
// and each is rebuilt to the former owner's roadmap.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "integration/metrics_probe.hpp"
#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

using namespace std::chrono_literals;

class FleetTakeoverTest : public ServiceTest {};

// Before (issue 42), the fleet thread ran each takeover to its end before the next: b's log read
// "takes it over" for one scene, its outcome, then the other's. Now both start in one pass.
TEST_F(FleetTakeoverTest, TheScenesOfAHolderThatLeftAreTakenOverAtOnce) {
  auto a = start("a", {"--memory-budget-mb", kNoBudget});
  Client client(client_options(domain_));
  const std::vector<std::string> scenes = {"s0", "s1", "s2"};
  for (const std::string& scene : scenes)
    ASSERT_EQ(load_and_build(client, scene, ispars_build(3000, 3)).server_id, "a");
  auto b = start("b", {"--memory-budget-mb", kNoBudget, "--metrics", "127.0.0.1:0"});
  const int b_metrics = metrics_port(b->log());
  ASSERT_TRUE(eventually([&] { return other_daemons_counted_on(b_metrics) == 1; }, 30s, "b counts a")) << b->log();
  a->kill9();
  for (const std::string& scene : scenes) {
    const SceneStatus carried = idle_on(client, scene, "b", 60s);  // after a's lease and b's claim
    ASSERT_EQ(carried.server_id, "b") << b->log();
    EXPECT_EQ(carried.samples_done, 3000u) << b->log();
    EXPECT_EQ(roadmap_digest(client.snapshot(scene).roadmap),
              reference_digest(scene_dir_ / (scene + ".yaml"), 3000, 3));
  }
  const std::string log = b->log();
  std::size_t first_outcome = std::string::npos;
  for (const std::string& scene : scenes) {
    first_outcome = std::min(first_outcome, log.find("scene '" + scene + "' taken over from a"));
  }
  ASSERT_NE(first_outcome, std::string::npos) << log;
  for (const std::string& scene : scenes) {
    const std::size_t started = log.find("left while holding scene '" + scene + "'; this daemon takes it over");
    ASSERT_NE(started, std::string::npos) << log;
    EXPECT_LT(started, first_outcome) << "scene " << scene << "'s takeover waited for another's:\n" << log;
  }
}

}  // namespace
}  // namespace ispars::test
