// The tour desk: tours admitted up to their bound, each leasing its worst case until it ends;
// stopped by scene, and a tour stopped while it waited for a worker fails by name.

#include "ispars/service/tour_desk.hpp"

#include <gtest/gtest.h>

#include <mutex>

#include "ispars/params/input_error.hpp"
#include "server/service_waits.hpp"
#include "server/unit_service.hpp"
#include "support/eventually.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

using namespace std::chrono_literals;
using test::eventually;

class TourDeskTest : public ::testing::Test {
 protected:
  void SetUp() override { service_ = test::service_with_s0(dir_.path(), 1500); }
  // Callbacks that count progress with a tour, and record how each tour ended.
  TourCallbacks callbacks() {
    TourCallbacks c;
    c.progress = [this](double, double cost, double) {
      progress_ += cost > 0.0;
      tourless_progress_ += cost <= 0.0;  // none may come before the first tour
    };
    c.done = [this](TourOutcome) {
      std::lock_guard lock(mutex_);
      ended_.push_back("done");
    };
    c.failed = [this](const std::string& error) {
      std::lock_guard lock(mutex_);
      ended_.push_back(error);
    };
    return c;
  }
  std::vector<std::string> ended() {
    std::lock_guard lock(mutex_);
    return ended_;
  }
  static TourRequest long_tour() {
    TourRequest t;
    t.budget_seconds = 600.0;  // runs until stopped
    return t;
  }
  test::TempDir dir_;
  std::unique_ptr<RoadmapService> service_;
  std::shared_ptr<MemoryBudget> budget_ = MemoryBudget::make(1e12);
  std::atomic<bool> stopping_{false};
  std::atomic<int> progress_{0};
  std::atomic<int> tourless_progress_{0};
  std::mutex mutex_;
  std::vector<std::string> ended_;
};

TEST_F(TourDeskTest, ToursAreAdmittedUpToTheBoundAndLeaseUntilTheyEnd) {
  TourDesk desk(1, 1, budget_, stopping_);
  desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());
  EXPECT_GT(budget_->leased(), 0.0);
  try {
    desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());
    ADD_FAILURE() << "a second tour was admitted past the bound";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("busy: 1 tours are queued or running"), std::string::npos) << e.what();
  }
  // Stopped once it has a tour, so that it ends with its best.
  ASSERT_TRUE(eventually([&] { return progress_ > 0; }, 60s, "the tour reports a tour"));
  EXPECT_EQ(desk.stop("s1"), 0u);  // another scene's stop leaves it
  EXPECT_EQ(desk.stop("s0"), 1u);
  ASSERT_TRUE(eventually([&] { return ended().size() == 1; }, 30s, "the stopped tour ends"));
  EXPECT_EQ(ended()[0], "done");
  EXPECT_EQ(tourless_progress_, 0) << "a progress came before the first tour (its cost 0 is no tour's)";
  ASSERT_TRUE(eventually([&] { return budget_->leased() == 0.0; }, 30s, "its lease is given back"));
  EXPECT_EQ(desk.stop("s0"), 0u);                                       // released: nothing left to stop
  desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());  // the place is free again
  EXPECT_EQ(desk.stop(""), 1u);
  desk.close();
}

TEST_F(TourDeskTest, ATourStoppedWhileItWaitedFailsByName) {
  TourDesk desk(1, 2, budget_, stopping_);
  desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());  // runs
  desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());  // waits for the worker
  ASSERT_TRUE(eventually([&] { return progress_ > 0; }, 60s, "the first tour reports a tour"));
  EXPECT_EQ(desk.stop("s0"), 2u);
  ASSERT_TRUE(eventually([&] { return ended().size() == 2; }, 30s, "both tours end"));
  EXPECT_EQ(ended()[0], "done");
  EXPECT_EQ(ended()[1], "request: scene: the tour was cancelled before it started");
  desk.close();
  stopping_ = true;
  try {
    desk.admit(service_->session("s0"), "s0", long_tour(), callbacks());
    ADD_FAILURE() << "a tour was admitted after the workers stopped";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the daemon is stopping"), std::string::npos) << e.what();
  }
  EXPECT_DOUBLE_EQ(budget_->leased(), 0.0);
}

}  // namespace
}  // namespace ispars::service
