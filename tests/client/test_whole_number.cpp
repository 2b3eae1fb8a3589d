// Whole-number flags of `ispars` (client/cli/whole_number.hpp): the text as typed, signs and
// overflow included.

#include "whole_number.hpp"

#include <gtest/gtest.h>

#include <string>

namespace ispars::cli {
namespace {

TEST(WholeNumber, ReadsDecimalDigitsWithASign) {
  bool negative = true;
  EXPECT_EQ(parse_whole_number("0", negative), 0u);
  EXPECT_FALSE(negative);
  EXPECT_EQ(parse_whole_number("+42", negative), 42u);
  EXPECT_EQ(parse_whole_number("007", negative), 7u);
  EXPECT_EQ(parse_whole_number("18446744073709551615", negative), 18446744073709551615u);
  EXPECT_EQ(parse_whole_number("-5", negative), 5u);
  EXPECT_TRUE(negative);
  EXPECT_EQ(parse_whole_number("-0", negative), 0u);
  EXPECT_FALSE(negative) << "-0 is zero";
}

TEST(WholeNumber, RefusesWhatIsNotAWholeNumber) {
  bool negative = false;
  for (const char* text : {"", "-", "+", "1e3", "2.5", "0x10", " 5", "5 ", "1,000", "18446744073709551616",
                           "99999999999999999999", "nan", "inf"}) {
    EXPECT_FALSE(parse_whole_number(text, negative).has_value()) << text;
  }
}

TEST(WholeNumber, TheCheckNamesTheRangeInItsUnit) {
  const CLI::Validator samples = whole_number(1, 1000, "samples");
  for (std::string ok : {"1", "1000", "+7"}) EXPECT_EQ(samples(ok), "") << ok;
  std::string text = "0";
  EXPECT_EQ(samples(text), "must be a whole number of samples from 1 to 1000, got '0'");
  text = "-5";
  EXPECT_EQ(samples(text), "must be a whole number of samples from 1 to 1000, got '-5'");
  text = "1001";
  EXPECT_EQ(samples(text), "must be a whole number of samples from 1 to 1000, got '1001'");
  text = "1e3";
  EXPECT_EQ(whole_number(0, 9, "")(text), "must be a whole number from 0 to 9, got '1e3'");
}

}  // namespace
}  // namespace ispars::cli
