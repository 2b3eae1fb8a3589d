// eventually() and throughout(): a condition that comes true passes, one that never does fails
// naming what was waited for; one that stops holding fails naming it too.

#include <gtest/gtest.h>

#include <string>

#include "support/eventually.hpp"

namespace ispars::test {
namespace {

using namespace std::chrono_literals;

TEST(Eventually, PassesOnceTheConditionHoldsAndFailsNamingItOtherwise) {
  int looks = 0;
  EXPECT_TRUE(eventually([&] { return ++looks == 3; }, 5s, "the third look", 1ms));
  EXPECT_EQ(looks, 3);
  const testing::AssertionResult never = eventually([] { return false; }, 20ms, "the scene is served", 1ms);
  ASSERT_FALSE(never);
  EXPECT_NE(std::string(never.message()).find("the scene is served: not within 20 ms"), std::string::npos)
      << never.message();
}

TEST(Eventually, ThroughoutFailsWhenTheConditionStopsHolding) {
  int looks = 0;
  EXPECT_TRUE(throughout([&] { return ++looks > 0; }, 20ms, "always", 1ms));
  EXPECT_GE(looks, 2);
  looks = 0;
  const testing::AssertionResult stopped = throughout([&] { return ++looks < 3; }, 5s, "one holder", 1ms);
  ASSERT_FALSE(stopped);
  EXPECT_EQ(looks, 3);
  EXPECT_NE(std::string(stopped.message()).find("one holder: stopped holding after"), std::string::npos);
}

}  // namespace
}  // namespace ispars::test
