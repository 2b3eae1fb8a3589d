// The memory budget: reservations of roadmap peaks, leases for passing work, and the service's
// snapshots and tours refused as busy (nothing stored changed) when the budget has no room.

#include "ispars/service/memory_budget.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "server/service_waits.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

planning::BuildCost cost_of(double held, double peak) {
  planning::BuildCost c;
  c.vertices = 10;
  c.edges = 20;
  c.bytes = held;
  c.peak_bytes = peak;
  return c;
}

std::string refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const params::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MemoryBudget, AScenesPeakIsReservedOnceAndARefusalChangesNothing) {
  const auto budget = MemoryBudget::make(1000.0);
  budget->admit("a", cost_of(100.0, 400.0));
  EXPECT_EQ(budget->reserved(), 400.0) << "the peak is reserved, not the steady state";
  budget->admit("a", cost_of(200.0, 600.0));
  EXPECT_EQ(budget->reserved(), 600.0) << "a scene's new admission replaces its old one";
  const std::string refused = refusal([&] { budget->admit("b", cost_of(100.0, 401.0)); });
  EXPECT_NE(refused.find("request: samples: the roadmap would hold about"), std::string::npos) << refused;
  EXPECT_NE(refused.find("while its store compacts"), std::string::npos) << refused;
  EXPECT_EQ(budget->reserved(), 600.0);
  budget->admit("b", cost_of(100.0, 400.0));
  budget->set_reserved("a", 0.0);
  EXPECT_EQ(budget->reserved(), 400.0);
  budget->set_reserved("c", 5000.0);  // a stored roadmap is held whatever the budget
  EXPECT_EQ(budget->reserved(), 5400.0);
}

TEST(MemoryBudget, LeasesFitBesideTheReservationsAndGiveBackWhenDropped) {
  const auto budget = MemoryBudget::make(1000.0);
  budget->admit("a", cost_of(100.0, 600.0));
  auto first = budget->lease(300.0, "a snapshot of scene 'a'");
  EXPECT_EQ(budget->leased(), 300.0);
  const std::string refused = refusal([&] { (void)budget->lease(101.0, "a tour of scene 'a'"); });
  EXPECT_NE(refused.find("request: kind: busy: a tour of scene 'a' would need"), std::string::npos) << refused;
  EXPECT_NE(refused.find("retry later"), std::string::npos) << refused;
  EXPECT_EQ(budget->leased(), 300.0) << "a refused lease takes nothing";
  first->shrink_to(50.0);
  EXPECT_EQ(budget->leased(), 50.0);
  auto second = budget->lease(350.0, "a tour");
  first.reset();
  EXPECT_EQ(budget->leased(), 350.0);
  std::weak_ptr<MemoryBudget> alive = budget;
  {
    const auto keep = second;
    second.reset();
    EXPECT_EQ(budget->leased(), 350.0) << "held until the last holder lets go";
  }
  EXPECT_EQ(budget->leased(), 0.0);
}

// A build does not take memory that running work holds: admitted beside the reservations, it is
// refused as busy while leases fill the rest (before, leases were not counted, and a build could
// start with the budget already spent by tours); a reclaimer (kept snapshot encodings) is asked
// first, and what it gives back is counted.
TEST(MemoryBudget, AnAdmissionCountsTheLeasesHeldAfterTheReclaimerGaveBackWhatItCould) {
  const auto budget = MemoryBudget::make(1000.0);
  budget->admit("a", cost_of(100.0, 400.0));
  auto tour = budget->lease(300.0, "a tour of scene 'a'");
  std::shared_ptr<MemoryLease> cached = budget->lease(200.0, "a snapshot of scene 'a'");
  int reclaims = 0;
  budget->set_reclaimer([&] {
    ++reclaims;
    cached.reset();
  });
  budget->admit("b", cost_of(100.0, 300.0));  // fits once the cached encoding gave its 200 back
  EXPECT_EQ(reclaims, 1);
  EXPECT_EQ(budget->reserved(), 700.0);
  const std::string refused = refusal([&] { budget->admit("c", cost_of(10.0, 1.0)); });
  EXPECT_NE(refused.find("request: kind: busy: the roadmap would hold"), std::string::npos) << refused;
  EXPECT_NE(refused.find("running tours and snapshot encodings hold"), std::string::npos) << refused;
  EXPECT_EQ(reclaims, 2);
  EXPECT_EQ(budget->reserved(), 700.0) << "a refusal reserves nothing";
  tour.reset();
  budget->admit("c", cost_of(10.0, 1.0));
  // Beyond the budget whatever the leases: refused by its samples, as before.
  const std::string too_big = refusal([&] { budget->admit("d", cost_of(10.0, 5000.0)); });
  EXPECT_NE(too_big.find("request: samples:"), std::string::npos) << too_big;
}

TEST(MemoryBudget, ALeaseOutlivesItsBudgetsOwner) {
  auto budget = MemoryBudget::make(100.0);
  auto lease = budget->lease(10.0, "work");
  budget.reset();  // the lease keeps it alive
  lease.reset();
  SUCCEED();
}

// A service whose budget leaves no room beside a stored roadmap: snapshots and tours of it are
// refused as busy, and the roadmap is unchanged.
TEST(MemoryBudgetService, SnapshotsAndToursAreRefusedAsBusyWhenTheBudgetHasNoRoom) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "scenes");
  std::ofstream(dir.path() / "scenes" / "s0.yaml") << "procedural: {kind: tank_tower, seed: 1}\n";
  ServiceSettings settings;
  settings.server_id = "unit";
  settings.scene_dir = dir.path() / "scenes";
  settings.data_dir = dir.path() / "data";
  settings.build_workers = 1;
  settings.tour_workers = 1;
  double reserved = 0.0;
  std::uint64_t digest = 0;
  {
    RoadmapService service(settings, {});
    (void)service.load("s0");
    BuildRequest build;
    build.samples = 1500;
    service.build("s0", build);
    ASSERT_EQ(test::wait_idle(service, "s0").samples_done, 1500u);
    reserved = service.session("s0")->expected_cost().peak_bytes;
    digest = roadmap_digest(*service.session("s0")->published().roadmap);
    (void)service.snapshot("s0", 0, 0, 0);  // fits in an unlimited budget
  }
  settings.memory_budget_bytes = reserved + 1024.0;  // the stored roadmap's peak and a KiB
  RoadmapService service(settings, {});
  service.load_stored_roadmaps();
  ASSERT_EQ(service.stats("s0").samples_done, 1500u);
  const std::string snapshot = refusal([&] { (void)service.snapshot("s0", 0, 0, 0); });
  EXPECT_NE(snapshot.find("request: kind: busy: a snapshot of scene 's0' would need"), std::string::npos) << snapshot;
  const std::string tour = refusal([&] { service.start_tour("s0", TourRequest{}, {}); });
  EXPECT_NE(tour.find("request: kind: busy: a tour of scene 's0' would need"), std::string::npos) << tour;
  EXPECT_EQ(roadmap_digest(*service.session("s0")->published().roadmap), digest);
  EXPECT_EQ(service.stats("s0").samples_done, 1500u);
}

}  // namespace
}  // namespace ispars::service
