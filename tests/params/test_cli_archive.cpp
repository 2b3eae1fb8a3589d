// Declared parameters as CLI11 flags: named, typed, ranged and documented as declared.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ispars/params/cli_archive.hpp"

namespace ispars::params {
namespace {

constexpr Spec<double> kCliSlack{"stretch_slack", 0.0, 1.0, "the slack"};
constexpr Spec<std::uint64_t> kCliAfter{"stretch_slack_after", 0, 1'000'000'000'000, "where the slack starts"};

struct Slack {
  std::optional<double> stretch_slack;
  std::optional<std::uint64_t> stretch_slack_after;
  static void describe(auto& self, auto&& field) {
    field(kCliSlack, self.stretch_slack);
    field(kCliAfter, self.stretch_slack_after);
  }
};

// Parses `args` into a fresh app with the flags of Slack; "" when they parse, else CLI11's message.
std::string parse_flags(std::vector<std::string> args, Slack& slack) {
  CLI::App app;
  add_flags(app, slack);
  std::reverse(args.begin(), args.end());  // CLI11 takes a reversed vector
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(ParamCli, AFlagIsNamedTypedRangedAndDocumentedAsItsParameterIsDeclared) {
  Slack s;
  EXPECT_EQ(parse_flags({"--stretch-slack", "0.5", "--stretch-slack-after", "20000"}, s), "");
  EXPECT_EQ(s.stretch_slack, 0.5);
  EXPECT_EQ(s.stretch_slack_after, 20000u);
  Slack fresh;
  EXPECT_EQ(parse_flags({}, fresh), "");
  EXPECT_FALSE(fresh.stretch_slack) << "a flag not given leaves its member absent";
  EXPECT_EQ(parse_flags({"--stretch-slack-after", "2.5"}, s),
            "--stretch-slack-after: must be a whole number in [0, 1000000000000], got 2.5");
  EXPECT_EQ(parse_flags({"--stretch-slack-after", "-1"}, s),
            "--stretch-slack-after: must be a whole number in [0, 1000000000000], got -1");
  EXPECT_EQ(parse_flags({"--stretch-slack", "1"}, s), "");
  EXPECT_NE(parse_flags({"--stretch-slack", "1.0001"}, s), "");
  EXPECT_EQ(parse_flags({"--stretch-slack-after", "1000000000000"}, s), "");
  EXPECT_NE(parse_flags({"--stretch-slack-after", "1000000000001"}, s), "");
  CLI::App app;
  add_flags(app, s);
  const std::string help = app.help();
  EXPECT_NE(help.find("--stretch-slack-after INT"), std::string::npos) << help;
  EXPECT_NE(help.find("--stretch-slack FLOAT"), std::string::npos) << help;
  EXPECT_NE(help.find("where the slack starts; a whole number in [0, 1000000000000]"), std::string::npos) << help;
}

}  // namespace
}  // namespace ispars::params
