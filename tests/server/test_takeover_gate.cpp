// TakeoverGate: a request for a scene being taken over waits until the takeover resumed its
// work, and no longer than the bound; other scenes never wait.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "ispars/server/takeover_gate.hpp"

namespace ispars::server {
namespace {

using Clock = std::chrono::steady_clock;

TEST(TakeoverGate, ARequestWaitsUntilTheTakeoverIsDone) {
  TakeoverGate gate;
  std::atomic<bool> done{false};
  std::atomic<bool> waited_for_it{false};
  std::thread request;
  {
    const auto held = gate.hold("s0");
    request = std::thread([&] {
      const bool free = gate.wait("s0");
      waited_for_it = free && done.load();
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    done = true;  // the takeover resumed the work; the guard goes next
  }
  request.join();
  EXPECT_TRUE(waited_for_it) << "the request went on before the takeover was done";
}

TEST(TakeoverGate, OtherScenesAndFreeScenesNeverWait) {
  TakeoverGate gate;
  EXPECT_TRUE(gate.wait("s0", std::chrono::milliseconds(0)));
  const auto held = gate.hold("s0");
  const auto start = Clock::now();
  EXPECT_TRUE(gate.wait("s1"));
  EXPECT_LT(Clock::now() - start, std::chrono::milliseconds(500));
  EXPECT_FALSE(gate.wait("s0", std::chrono::milliseconds(0)));  // the control: s0 is held
}

TEST(TakeoverGate, AHungTakeoverHoldsARequestNoLongerThanTheBound) {
  TakeoverGate gate;
  const auto held = gate.hold("s0");
  const auto start = Clock::now();
  EXPECT_FALSE(gate.wait("s0", std::chrono::milliseconds(100)));
  EXPECT_GE(Clock::now() - start, std::chrono::milliseconds(100));
}

TEST(TakeoverGate, TwoTakeoversOfOneSceneHoldUntilBothAreDone) {
  TakeoverGate gate;
  auto first = std::make_unique<TakeoverGate::Held>(gate, "s0");
  {
    const auto second = gate.hold("s0");
    first.reset();
    EXPECT_FALSE(gate.wait("s0", std::chrono::milliseconds(0)));
  }
  EXPECT_TRUE(gate.wait("s0", std::chrono::milliseconds(0)));
}

}  // namespace
}  // namespace ispars::server
