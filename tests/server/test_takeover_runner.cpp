// TakeoverRunner: takeovers of different scenes run at once (one that waits does not hold the
// others back), one scene is taken over once at a time, at most kMaxRunning run, and a stop
// waits for those running and starts no more.

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <string>
#include <thread>

#include "ispars/server/takeover_runner.hpp"

namespace ispars::server {
namespace {

using namespace std::chrono_literals;

// Waits (bounded) until the runner has seen `scene`'s work return.
bool finished(const TakeoverRunner& runner, const std::string& scene) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (runner.running(scene)) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::yield();
  }
  return true;
}

TEST(TakeoverRunner, ATakeoverThatWaitsDoesNotHoldAnotherBack) {
  TakeoverRunner runner;
  std::promise<void> second_ran;
  std::promise<bool> first_saw_it;
  ASSERT_TRUE(runner.start("a", [&, ran = second_ran.get_future().share()] {
    first_saw_it.set_value(ran.wait_for(10s) == std::future_status::ready);
  }));
  EXPECT_TRUE(runner.running("a"));
  ASSERT_TRUE(runner.start("b", [&] { second_ran.set_value(); }));
  EXPECT_TRUE(first_saw_it.get_future().get()) << "the second takeover waited for the first";
  EXPECT_TRUE(finished(runner, "a"));
  EXPECT_TRUE(finished(runner, "b"));
}

TEST(TakeoverRunner, OneSceneIsTakenOverOnceAtATimeAndAtMostKMaxRunningRun) {
  TakeoverRunner runner;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  for (std::size_t i = 0; i < TakeoverRunner::kMaxRunning; ++i) {
    std::string scene = "s";
    scene += std::to_string(i);  // (not "s" + ...: GCC 12's -Wrestrict false alarm)
    ASSERT_TRUE(runner.start(scene, [released] { released.wait(); }));
  }
  EXPECT_FALSE(runner.start("s0", [] {}));     // running
  EXPECT_FALSE(runner.start("other", [] {}));  // every runner busy
  release.set_value();
  ASSERT_TRUE(finished(runner, "s0"));
  bool ran = false;
  EXPECT_TRUE(runner.start("s0", [&] { ran = true; }));  // finished: taken over again if asked
  ASSERT_TRUE(finished(runner, "s0"));
  runner.stop();
  EXPECT_TRUE(ran);
}

TEST(TakeoverRunner, AStopWaitsForThoseRunningAndStartsNoMore) {
  TakeoverRunner runner;
  std::promise<void> started;
  bool ended = false;
  ASSERT_TRUE(runner.start("a", [&] {
    started.set_value();
    std::this_thread::sleep_for(50ms);  // the takeover's own work, not a wait of the test
    ended = true;
  }));
  started.get_future().wait();
  runner.stop();
  EXPECT_TRUE(ended);
  EXPECT_FALSE(runner.running("a"));
  EXPECT_FALSE(runner.start("b", [] {}));
}

}  // namespace
}  // namespace ispars::server
