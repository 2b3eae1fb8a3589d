// A daemon's stop never hangs a test. isparsd's own watchdog ends a stop that stalls, 5 s after
// the signal, with exit status 4; LocalDaemon gives up on a daemon that has not exited
// LocalDaemon::kStopDeadline after SIGTERM (its threads' stacks go into its log, then SIGKILL).
// Before, a daemon whose stop hung in Fast DDS held a test in waitpid for 600 s.

#include <gtest/gtest.h>
#include <signal.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ispars/local/local_daemon.hpp"
#include "support/test_support.hpp"

namespace ispars::test {
namespace {

using ispars::local::LocalDaemon;
using StopClock = std::chrono::steady_clock;

// isparsd's exit status when its stop watchdog ended the stop, and that watchdog's deadline
// (server/daemon/include/ispars/server/stop_watchdog.hpp; docs/operations.md, "Signals").
constexpr int kWatchdogExitStatus = 4;
constexpr std::chrono::seconds kWatchdogDeadline{5};
// A stop ended by the watchdog may take this long past its deadline (logging, _exit, the reap).
constexpr std::chrono::seconds kWatchdogSlack{3};
// What LocalDaemon may take past its deadline when it gives up: gdb's stacks (bounded at 25 s;
// 1.4 s measured) and the SIGKILL.
constexpr std::chrono::seconds kGiveUpSlack{30};

// One daemon on a domain of its own, with a scene directory and a data directory.
class StopTestDaemon {
 public:
  explicit StopTestDaemon(const std::vector<std::string>& environment = {}) {
    local::write_tank_tower_scenes(dir_.path() / "scenes", {"s0"});
    daemon_ = std::make_unique<local::LocalDaemon>(ISPARS_DAEMON, local::random_domain(), dir_.path() / "data",
                                                   dir_.path() / "scenes", "stop", std::vector<std::string>{}, "",
                                                   environment);
  }
  std::unique_ptr<local::LocalDaemon>& daemon() { return daemon_; }

 private:
  TempDir dir_;  // declared first: outlives the daemon
  std::unique_ptr<local::LocalDaemon> daemon_;
};

// Whether process `pid` is gone for good (reaped: not even a zombie is left).
bool process_gone(pid_t pid) { return ::kill(pid, 0) == -1 && errno == ESRCH; }

// The log holds the stacks of the main thread of `pid` (gdb names it by its LWP, the pid).
bool log_holds_stacks_of(const std::string& log, pid_t pid) {
  return mentions(log, "every thread's stack of pid " + std::to_string(pid)) &&
         mentions(log, "(LWP " + std::to_string(pid) + ")");
}

TEST(LocalDaemonStopTest, TerminateGivesUpOnADaemonThatNeverExitsAndLeavesItsStacksInItsLog) {
  StopTestDaemon d;
  local::LocalDaemon& daemon = *d.daemon();
  const pid_t pid = daemon.pid();
  ASSERT_EQ(::kill(pid, SIGSTOP), 0);  // it can no longer act on SIGTERM, nor its watchdog fire
  const auto start = StopClock::now();
  EXPECT_EQ(daemon.terminate(), local::LocalDaemon::kStopTimedOut);
  const auto took = StopClock::now() - start;
  EXPECT_TRUE(daemon.stop_timed_out());
  EXPECT_GE(took, local::LocalDaemon::kStopDeadline);
  EXPECT_LT(took, local::LocalDaemon::kStopDeadline + kGiveUpSlack);
  EXPECT_FALSE(daemon.alive());
  EXPECT_TRUE(process_gone(pid)) << "the daemon was neither killed nor reaped";
  EXPECT_TRUE(log_holds_stacks_of(daemon.log(), pid)) << daemon.log();
}

TEST(LocalDaemonStopTest, TheDestructorGivesUpOnADaemonThatNeverExits) {
  StopTestDaemon d;
  const pid_t pid = d.daemon()->pid();
  ASSERT_EQ(::kill(pid, SIGSTOP), 0);
  const auto start = StopClock::now();
  d.daemon().reset();
  const auto took = StopClock::now() - start;
  EXPECT_GE(took, local::LocalDaemon::kStopDeadline);
  EXPECT_LT(took, local::LocalDaemon::kStopDeadline + kGiveUpSlack);
  EXPECT_TRUE(process_gone(pid)) << "the daemon was neither killed nor reaped";
}

// The stop stalls at a point a test hook names (ISPARS_TEST_STALL_STOP, server/daemon/src/main.cpp), as
// it stalled in Fast DDS: the daemon's watchdog ends it with its own status, within its deadline,
// and its log says what the stop was waiting for.
TEST(DaemonStopWatchdogTest, AStopThatStallsEndsWithTheWatchdogsStatusAfterItsDeadline) {
  StopTestDaemon d({"ISPARS_TEST_STALL_STOP=1"});
  local::LocalDaemon& daemon = *d.daemon();
  const auto start = StopClock::now();
  EXPECT_EQ(daemon.terminate(), kWatchdogExitStatus) << daemon.log();
  const auto took = StopClock::now() - start;
  EXPECT_FALSE(daemon.stop_timed_out()) << "the daemon did not end its own stop";
  EXPECT_GE(took, kWatchdogDeadline);
  EXPECT_LT(took, kWatchdogDeadline + kWatchdogSlack);
  EXPECT_TRUE(mentions(daemon.log(),
                       "the stop did not finish within 5 s (waiting for a stall a test asked for "
                       "(ISPARS_TEST_STALL_STOP)); exiting with status 4"))
      << daemon.log();
}

}  // namespace
}  // namespace ispars::test
