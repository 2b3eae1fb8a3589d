// The recipe's declared parameters as flags: typed, ranged and documented as declared.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ispars/roadmap/recipe_flags.hpp"

namespace ispars {
namespace {

// Parses `args` (after the program name) into a fresh app with the two slack flags; "" when they
// parse, else CLI11's message.
std::string parse(std::vector<std::string> args, double& slack, std::uint64_t& after) {
  CLI::App app;
  add_recipe_flag(app, "stretch_slack", slack);
  add_recipe_flag(app, "stretch_slack_after", after);
  std::reverse(args.begin(), args.end());  // CLI11 takes a reversed vector
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(RecipeFlags, AFlagIsNamedTypedRangedAndDocumentedAsItsParameterIsDeclared) {
  EXPECT_EQ(recipe_flag_name("stretch_slack_after"), "--stretch-slack-after");
  double slack = 0.0;
  std::uint64_t after = 0;
  EXPECT_EQ(parse({"--stretch-slack", "0.5", "--stretch-slack-after", "20000"}, slack, after), "");
  EXPECT_EQ(slack, 0.5);
  EXPECT_EQ(after, 20000u);
  // A count parses as an integer only; each end of a declared range is inclusive, past it refused.
  EXPECT_NE(parse({"--stretch-slack-after", "2.5"}, slack, after), "");
  EXPECT_NE(parse({"--stretch-slack-after", "-1"}, slack, after), "");
  EXPECT_EQ(parse({"--stretch-slack", "1"}, slack, after), "");
  EXPECT_NE(parse({"--stretch-slack", "1.0001"}, slack, after), "");
  EXPECT_NE(parse({"--stretch-slack", "-0.1"}, slack, after), "");
  EXPECT_EQ(parse({"--stretch-slack-after", "1000000000000"}, slack, after), "");
  EXPECT_NE(parse({"--stretch-slack-after", "1000000000001"}, slack, after), "");
  // The help is the declared doc.
  CLI::App app;
  double p_accept = 0.2;
  add_recipe_flag(app, "p_accept", p_accept);
  EXPECT_NE(app.help().find(std::string(recipe_override("p_accept").doc)), std::string::npos) << app.help();
}

TEST(RecipeFlags, AFlagOfAnotherTypeThanDeclaredOrAnUndeclaredNameIsAProgrammingError) {
  CLI::App app;
  double real = 0.0;
  std::uint64_t count = 0;
  EXPECT_THROW(add_recipe_flag(app, "stretch_slack_after", real), std::logic_error);
  EXPECT_THROW(add_recipe_flag(app, "stretch", count), std::logic_error);
  EXPECT_THROW(add_recipe_flag(app, "colour", real), std::out_of_range);
}

}  // namespace
}  // namespace ispars
