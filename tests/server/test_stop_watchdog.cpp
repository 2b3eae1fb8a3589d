// StopWatchdog: a stop that has not finished by its deadline is ended, naming the step it was
// waiting for; one that finished in time never is. The daemon's own watchdog (arm_stop_watchdog)
// exits with kExitStopTimedOut after logging that step.

#include <gtest/gtest.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "ispars/server/stop_watchdog.hpp"

namespace ispars::server {
namespace {

using Clock = std::chrono::steady_clock;

// What a test's watchdog saw when it expired.
struct ExpiryRecord {
  std::mutex mutex;
  std::condition_variable done;
  bool expired = false;
  std::string step;
  Clock::time_point at;

  StopWatchdog::Expiry callback() {
    return [this](const char* s) {
      std::lock_guard lock(mutex);
      expired = true;
      step = s != nullptr ? s : "(none)";
      at = Clock::now();
      done.notify_all();
    };
  }
  bool wait_for_expiry(std::chrono::milliseconds limit) {
    std::unique_lock lock(mutex);
    return done.wait_for(lock, limit, [this] { return expired; });
  }
};

TEST(StopWatchdog, AStopPastItsDeadlineIsEndedNamingTheStepItWaitedFor) {
  ExpiryRecord record;
  note_stop_step("the first step");
  const auto start = Clock::now();
  StopWatchdog watchdog(std::chrono::milliseconds(200), record.callback());
  note_stop_step("the DDS participant's deletion");  // the step it hangs in
  ASSERT_TRUE(record.wait_for_expiry(std::chrono::seconds(5))) << "the watchdog never expired";
  EXPECT_EQ(record.step, "the DDS participant's deletion");
  EXPECT_GE(record.at - start, std::chrono::milliseconds(200)) << "it expired before its deadline";
  note_stop_step(nullptr);
}

TEST(StopWatchdog, AStopThatFinishesInTimeIsNeverEnded) {
  ExpiryRecord record;
  const auto start = Clock::now();
  {
    StopWatchdog watchdog(std::chrono::milliseconds(300), record.callback());
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // a stop that finishes at once
  }
  EXPECT_LT(Clock::now() - start, std::chrono::milliseconds(250)) << "disarming it waited for the deadline";
  EXPECT_FALSE(record.wait_for_expiry(std::chrono::milliseconds(600))) << "a disarmed watchdog expired";
}

// The daemon's watchdog, in a child process: the stop stalls at a named step, and the process
// ends kStopDeadline later with kExitStopTimedOut, its log naming the step.
TEST(StopWatchdog, TheDaemonsWatchdogExitsWithItsStatusAndLogsTheStep) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  const auto start = Clock::now();
  EXPECT_EXIT(
      {
        spdlog::set_default_logger(std::make_shared<spdlog::logger>(
            "isparsd", std::make_shared<spdlog::sinks::stderr_sink_mt>()));  // the death test reads stderr
        arm_stop_watchdog();
        note_stop_step("a stalled step");
        for (;;) ::pause();
      },
      ::testing::ExitedWithCode(kExitStopTimedOut),
      "the stop did not finish within " + std::to_string(kStopDeadline.count()) +
          " s \\(waiting for a stalled step\\); exiting with status " + std::to_string(kExitStopTimedOut));
  EXPECT_GE(Clock::now() - start, kStopDeadline);
  EXPECT_LT(Clock::now() - start, kStopDeadline + std::chrono::seconds(5));
}

}  // namespace
}  // namespace ispars::server
