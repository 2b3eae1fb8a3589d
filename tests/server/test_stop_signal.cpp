// The background threads' shared wait: a wake ends the next wait_for, a stop ends every wait.

#include "ispars/server/stop_signal.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "support/eventually.hpp"

namespace ispars::server {
namespace {

using namespace std::chrono_literals;
using test::eventually;

TEST(StopSignal, AWaitRunsItsPeriodUnlessWokenOrStopped) {
  StopSignal signal;
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(signal.wait_for(50ms));
  EXPECT_TRUE(signal.idle_for(50ms));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 100ms);
  EXPECT_FALSE(signal.stopped());
}

TEST(StopSignal, AWakeBeforeTheWaitIsNotLost) {
  StopSignal signal;
  signal.wake();  // the fleet changed while the fleet thread was at work
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(signal.wait_for(60s));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 30s);
  // Taken by that wait: the next one runs its period.
  const auto again = std::chrono::steady_clock::now();
  EXPECT_TRUE(signal.wait_for(50ms));
  EXPECT_GE(std::chrono::steady_clock::now() - again, 50ms);
}

TEST(StopSignal, AWakeEndsAWaitForButNotASleep) {
  StopSignal signal;
  std::atomic<bool> waited{false};
  std::thread waiter([&] {
    EXPECT_TRUE(signal.wait_for(60s));
    waited = true;
  });
  EXPECT_TRUE(eventually(
      [&] {
        signal.wake();
        return waited.load();
      },
      30s, "a wake ends the wait"));
  waiter.join();
  signal.wake();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(signal.idle_for(100ms));
  EXPECT_GE(std::chrono::steady_clock::now() - start, 100ms);
}

TEST(StopSignal, AStopEndsEveryWaitNowAndLater) {
  StopSignal signal;
  std::atomic<int> waiting{0}, ended{0};
  std::thread fleet([&] {
    ++waiting;
    while (signal.wait_for(60s)) {
    }
    ++ended;
  });
  std::thread health([&] {
    ++waiting;
    while (signal.idle_for(60s)) {
    }
    ++ended;
  });
  ASSERT_TRUE(eventually([&] { return waiting == 2; }, 30s, "both threads reach their waits"));
  // Inside their waits now (a wait that returned early would be taken again, never end the loop).
  ASSERT_TRUE(test::throughout([&] { return ended == 0; }, 100ms, "both threads wait"));
  signal.stop();
  // The waits run 60 s: only the stop's notification ends them within this bound.
  EXPECT_TRUE(eventually([&] { return ended == 2; }, 30s, "both waits end at the stop"));
  fleet.join();
  health.join();
  EXPECT_TRUE(signal.stopped());
  const auto start = std::chrono::steady_clock::now();
  EXPECT_FALSE(signal.wait_for(60s));
  EXPECT_FALSE(signal.idle_for(60s));
  EXPECT_LT(std::chrono::steady_clock::now() - start, 30s);
}

}  // namespace
}  // namespace ispars::server
