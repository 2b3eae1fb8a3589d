// Text and list parameters (text_spec.hpp), an `int` id, and a rule after the range: each refused
// by name and in words, each accepted value left as given.

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "ispars/params/cli_archive.hpp"
#include "ispars/params/spec.hpp"
#include "ispars/params/text_spec.hpp"

namespace ispars::params {
namespace {

std::string no_shouting(const std::string& text) {
  return text.find('!') == std::string::npos ? std::string() : "'" + text + "' is shouted";
}
std::string even(std::uint64_t value) { return value % 2 == 0 ? std::string() : "must be even"; }

constexpr TextSpec kName{"name", "a name", 8, false, true, &no_shouting};
constexpr ListSpec kNames{"names", "some names", 2, 4};
constexpr Spec<int> kId{"id", 0, 232, "an id"};
constexpr Spec<std::uint64_t> kEven{"even", 0, 100, "an even count", Lower::closed, false, &even, "pair"};

TEST(ParamText, ATextIsBoundedThenRuled) {
  EXPECT_EQ(problem(kName, "tower"), "");
  EXPECT_EQ(problem(kName, ""), "");
  EXPECT_EQ(problem(kName, "towering!"), "is longer than 8 characters") << "the length is checked first";
  EXPECT_EQ(problem(kName, "tower!"), "'tower!' is shouted");
}

TEST(ParamText, AListIsBoundedInItemsAndInEachItemsLength) {
  EXPECT_EQ(problem(kNames, std::vector<std::string>{"a", "bcde"}), "");
  EXPECT_EQ(problem(kNames, std::vector<std::string>{"a", "b", "c"}), "has more than 2 items");
  EXPECT_EQ(problem(kNames, std::vector<std::string>{"abcde"}), "has an item longer than 4 characters");
}

TEST(ParamText, AnIntIdIsACountAndARuleFollowsTheRange) {
  EXPECT_EQ(parse(kId, "232").value, 232);
  EXPECT_EQ(parse(kId, "233").problem, "must be a whole number in [0, 232], got 233");
  EXPECT_EQ(parse(kId, "-1").problem, "must be a whole number in [0, 232], got -1");
  EXPECT_EQ(parse(kEven, "4").problem, "");
  EXPECT_EQ(parse(kEven, "5").problem, "must be even");
  EXPECT_EQ(parse(kEven, "101").problem, "must be a whole number in [0, 100], got 101") << "the range comes first";
  EXPECT_EQ(kEven.alias, "pair");
}

TEST(ParamText, ATextFlagIsCheckedAsDeclared) {
  std::string name = "default";
  CLI::App app;
  add_flag(app, kName, name);
  std::vector<std::string> args = {"tower", "--name"};  // CLI11 takes a reversed vector
  app.parse(args);
  EXPECT_EQ(name, "tower");
  args = {"tower!", "--name"};
  try {
    app.parse(args);
    FAIL() << "a shouted name was taken";
  } catch (const CLI::ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("'tower!' is shouted"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ispars::params
