// ispars-lab refuses the build requests the daemon refuses, in the daemon's words: each bad
// request run through `ispars-lab build` and `ispars-lab bench build`, and its refusal compared
// with make_recipe's (builders/recipe_builder.hpp), the check the daemon and Python run.

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include "ispars/params/cli_archive.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"

#include "lab_cli_fixture.hpp"

namespace ispars {
namespace {

using test::LabCli;

constexpr const char* kScene = ISPARS_SCENES_DIR "/demo_tank_tower.yaml";

// The problem make_recipe names for the request `flags` spell (parsed as the lab's flags are
// declared: --method, --variant and each override), or "" when it accepts it.
std::string daemon_problem(const std::string& flags) {
  CLI::App app;
  std::string method, variant;
  BuildRequest request;
  request.samples = 200;
  app.add_option("--method", method);
  app.add_option("--variant", variant);
  params::add_flags(app, request.overrides);
  std::vector<std::string> args;
  std::istringstream words(flags);
  for (std::string w; words >> w;) args.push_back(w);
  std::reverse(args.begin(), args.end());
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return std::string(e.what()).substr(std::string(e.what()).find(": ") + 2);  // the flag's own check
  }
  const planning::Scene scene = planning::Scene::load(kScene);
  try {
    set_method(request, method, variant, "request");
    (void)make_recipe("tower", scene, request, "request");
  } catch (const params::InputError& e) {
    return e.problem();
  }
  return "";
}

class LabRequests : public LabCli, public ::testing::WithParamInterface<const char*> {};

TEST_P(LabRequests, TheLabRefusesWhatTheDaemonRefusesWithTheSameMessage) {
  const std::string flags = GetParam();
  const std::string problem = daemon_problem(flags);
  ASSERT_NE(problem, "") << "make_recipe accepts " << flags;
  for (const std::string command : {"build", "bench build"}) {
    SCOPED_TRACE(command);
    const test::LabRun run = lab(command + " " + kScene + " --samples 200 " + flags);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find(problem), std::string::npos) << "expected: " << problem << "\ngot: " << run.err;
  }
}

INSTANTIATE_TEST_SUITE_P(BadRequests, LabRequests,
                         ::testing::Values("--method dense --stretch-slack 0.5",  // no stretch rules to slacken
                                           "--method ispars --variant alg1 --stretch-slack 0.2",
                                           "--method ispars --stretch-slack-after 100",  // a start without a slack
                                           "--method irisc --variant alg1",  // a variant of a method without one
                                           "--method ispars --sparse-delta 100000",  // off the scene's scale
                                           "--method ispars --dense-delta 0.000001",
                                           "--method spars --stretch 150",               // out of its declared range
                                           "--method ispars --stretch-slack-after 2.5",  // a count is whole
                                           "--method ispars2 --p-accept -0.5"));

TEST_F(LabCli, AnAcceptedRequestBuildsTheRecipeItNames) {
  const test::LabRun run =
      lab(std::string("build ") + kScene + " --method ispars --samples 300 --stretch 1.5 --stretch-slack 0.25 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(test::last_line(run.out));
  EXPECT_EQ(json["stretch_slack"], 0.25);
  EXPECT_EQ(json["variant"], "stretch");
}

}  // namespace
}  // namespace ispars
