// The gate between long readers (verify) and the writers that must not wait for them.

#include <gtest/gtest.h>

#include "ispars/service/reader_gate.hpp"

namespace ispars::service {
namespace {

using Clock = std::chrono::steady_clock;

TEST(ReaderGate, AHoldStopsTheRunningReadersWithItsReasonAndKeepsNewOnesOut) {
  ReaderGate gate;
  auto a = gate.enter(Clock::now() + std::chrono::hours(1));
  auto b = gate.enter(Clock::now() + std::chrono::hours(1));
  EXPECT_EQ(gate.readers(), 2u);
  EXPECT_TRUE(a->keep_going());
  {
    const auto hold = gate.hold_off("scene 'x' is being unloaded");
    EXPECT_FALSE(a->keep_going());
    EXPECT_FALSE(b->keep_going());
    EXPECT_EQ(a->why_stopped(), "scene 'x' is being unloaded");
    try {
      (void)gate.enter(Clock::now() + std::chrono::hours(1));
      ADD_FAILURE() << "a reader entered while a writer held readers off";
    } catch (const ReaderRefused& e) {
      EXPECT_STREQ(e.what(), "scene 'x' is being unloaded");
    }
  }
  b.reset();
  EXPECT_EQ(gate.readers(), 1u);
  auto c = gate.enter(Clock::now() + std::chrono::hours(1));
  EXPECT_TRUE(c->keep_going()) << "the hold outlived itself";
}

TEST(ReaderGate, StopAllStopsTheRunningOnesOnlyAndADeadlineStopsItsReader) {
  ReaderGate gate;
  auto a = gate.enter(Clock::now() + std::chrono::hours(1));
  gate.stop_all("the daemon is stopping");
  EXPECT_FALSE(a->keep_going());
  EXPECT_EQ(a->why_stopped(), "the daemon is stopping");
  auto late = gate.enter(Clock::now() + std::chrono::hours(1));
  EXPECT_TRUE(late->keep_going());
  auto timed = gate.enter(Clock::now() - std::chrono::milliseconds(1));
  EXPECT_FALSE(timed->keep_going());
  EXPECT_EQ(timed->why_stopped(), "its time ran out");
}

}  // namespace
}  // namespace ispars::service
