// A parameter's declaration: its range in words, the check, and text read as declared.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

#include "ispars/params/spec.hpp"

namespace ispars::params {
namespace {

constexpr Spec<double> kSpecReal{"real", 1.0, 100.0, "a real"};
constexpr Spec<double> kSpecPositive{"positive", 0.0, 1e6, "a positive real", Lower::open};
constexpr Spec<std::uint64_t> kSpecCount{"count", 1, 1000, "a count"};
constexpr Spec<bool> kSpecSwitch{"switch", false, true, "a switch"};

TEST(ParamSpec, TheRangeInWordsShowsWhichEndsAreIncluded) {
  EXPECT_EQ(range_text(kSpecReal), "in [1, 100]");
  EXPECT_EQ(range_text(kSpecPositive), "in (0, 1000000]");
  EXPECT_EQ(range_text(kSpecCount), "a whole number in [1, 1000]");
  EXPECT_EQ(range_text(kSpecSwitch), "true or false");
  EXPECT_EQ(flag_name("stretch_slack_after"), "--stretch-slack-after");
  EXPECT_EQ(type_name<double>(), "FLOAT");
  EXPECT_EQ(type_name<std::uint64_t>(), "INT");
}

TEST(ParamSpec, EachEndIsAcceptedOrRefusedAsDeclaredAndNonFiniteRealsNever) {
  EXPECT_EQ(problem(kSpecReal, 1.0), "");
  EXPECT_EQ(problem(kSpecReal, 100.0), "");
  EXPECT_EQ(problem(kSpecReal, std::nextafter(1.0, 0.0)), "must be in [1, 100], got 0.9999999999999999");
  EXPECT_NE(problem(kSpecReal, std::nextafter(100.0, 1e9)), "");
  EXPECT_NE(problem(kSpecPositive, 0.0), "") << "an open lower bound excludes itself";
  EXPECT_EQ(problem(kSpecPositive, 1e-300), "");
  EXPECT_NE(problem(kSpecReal, std::numeric_limits<double>::quiet_NaN()), "");
  EXPECT_NE(problem(kSpecPositive, std::numeric_limits<double>::infinity()), "");
  EXPECT_EQ(problem(kSpecCount, std::uint64_t{1}), "");
  EXPECT_EQ(problem(kSpecCount, std::uint64_t{0}), "must be a whole number in [1, 1000], got 0");
}

TEST(ParamSpec, ACountIsReadAsASignedWholeNumberThenRangeChecked) {
  EXPECT_EQ(parse(kSpecCount, "7").value, 7u);
  EXPECT_EQ(parse(kSpecCount, "1000").problem, "");
  EXPECT_EQ(parse(kSpecCount, "-1").problem, "must be a whole number in [1, 1000], got -1")
      << "never wrapped to 2^64 - 1";
  EXPECT_EQ(parse(kSpecCount, "1001").problem, "must be a whole number in [1, 1000], got 1001");
  EXPECT_EQ(parse(kSpecCount, "2.5").problem, "must be a whole number in [1, 1000], got 2.5");
  EXPECT_EQ(parse(kSpecCount, "99999999999999999999").problem,
            "must be a whole number in [1, 1000], got 99999999999999999999");
  EXPECT_EQ(parse(kSpecCount, "ten").problem, "expected a whole number, got 'ten'");
  EXPECT_EQ(parse(kSpecCount, "").problem, "expected a whole number, got ''");
  EXPECT_NE(parse(kSpecCount, " 5").problem, "");
  EXPECT_EQ(parse(kSpecCount, "+7").value, 7u) << "a sign as typed";
  EXPECT_EQ(parse(kSpecCount, "007").value, 7u);
  EXPECT_EQ(parse(kSpecCount, "-0").problem, "must be a whole number in [1, 1000], got 0")
      << "-0 is 0, below the range";
  EXPECT_EQ(parse(kSpecCount, "0x10").problem, "must be a whole number in [1, 1000], got 0x10");
  EXPECT_EQ(parse(kSpecCount, "1e3").problem, "must be a whole number in [1, 1000], got 1e3");
  EXPECT_EQ(parse(kSpecCount, "1,000").problem, "expected a whole number, got '1,000'");
}

TEST(ParamSpec, ARealMustBeWholeTextFiniteAndInRange) {
  EXPECT_EQ(parse(kSpecReal, "2.5").value, 2.5);
  EXPECT_EQ(parse(kSpecReal, "1e2").problem, "");
  EXPECT_EQ(parse(kSpecReal, "2.5x").problem, "expected a number, got '2.5x'");
  EXPECT_EQ(parse(kSpecReal, "nan").problem, "must be in [1, 100], got nan");
  EXPECT_NE(parse(kSpecPositive, "0").problem, "");
  EXPECT_TRUE(parse(kSpecSwitch, "yes").value);
  EXPECT_FALSE(parse(kSpecSwitch, "off").value);
  EXPECT_EQ(parse(kSpecSwitch, "maybe").problem, "expected true or false, got 'maybe'");
}

}  // namespace
}  // namespace ispars::params
