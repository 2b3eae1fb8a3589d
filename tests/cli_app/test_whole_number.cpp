// Whole-number flags of `ispars` that are no declared parameter (client/cli/whole_number.hpp):
// the text as typed, refused in the words every declared parameter uses.

#include "ispars/cli_app/whole_number.hpp"

#include <gtest/gtest.h>

#include <string>

namespace ispars::cli_app {
namespace {

TEST(WholeNumber, TheCheckNamesTheRangeAsEveryParameterDoes) {
  const CLI::Validator edges = whole_number(1, 1000);
  for (std::string ok : {"1", "1000", "+7", "007"}) EXPECT_EQ(edges(ok), "") << ok;
  for (const auto& [text, problem] : std::vector<std::pair<std::string, std::string>>{
           {"0", "must be a whole number in [1, 1000], got 0"},
           {"-5", "must be a whole number in [1, 1000], got -5"},
           {"1001", "must be a whole number in [1, 1000], got 1001"},
           {"1e3", "must be a whole number in [1, 1000], got 1e3"},
           {"2.5", "must be a whole number in [1, 1000], got 2.5"},
           {"18446744073709551616", "must be a whole number in [1, 1000], got 18446744073709551616"},
           {"five", "expected a whole number, got 'five'"},
           {"", "expected a whole number, got ''"}}) {
    std::string t = text;
    EXPECT_EQ(edges(t), problem) << text;
  }
  std::string any = "18446744073709551615";
  EXPECT_EQ(whole_number(0, kMaxSeed)(any), "") << "every 64-bit seed";
}

}  // namespace
}  // namespace ispars::cli_app
