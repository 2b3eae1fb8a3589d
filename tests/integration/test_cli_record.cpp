// `ispars record` against a real isparsd, read back by readers written elsewhere: @mcap/core's
// stream and indexed readers open the file, ajv checks every message against @foxglove/schemas'
// foxglove.SceneUpdate, and replaying the updates (deletions, then entities by id) gives the
// roadmap `stats` reports, vertex for vertex, edge for edge, and the tour the daemon flew.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "integration/cli_fixture.hpp"

namespace ispars::test {
namespace {

class CliRecordTest : public CliTest {
 protected:
  CliRun cli(const std::string& args) { return run(common_ + " " + args, dir_); }
  nlohmann::json check(const std::filesystem::path& mcap) {
    const auto [status, output] =
        run_command("NODE_PATH='" + std::string(ISPARS_READERS_NODE_MODULES) + "' timeout -k 5 120 node '" +
                    ISPARS_READERS_DIR + "/check_mcap.cjs' '" + mcap.string() + "' 2>&1");
    if (status != 0) throw std::runtime_error("check_mcap.cjs failed (" + std::to_string(status) + "): " + output);
    return nlohmann::json::parse(output);
  }
};

TEST_F(CliRecordTest, ARecordingOfABuildReplaysToTheRoadmapAndItsTour) {
  start();
  ASSERT_EQ(cli("scenes load tower").code, 0);
  ASSERT_EQ(cli("build tower --method ispars --samples 20000 --seed 4").code, 0);
  const auto mcap = dir_.path() / "tower.mcap";
  // Started while the build runs: the file holds several batches, not one snapshot.
  const CliRun recorded = cli("record tower --out " + mcap.string() + " --until-idle --tour 1");
  ASSERT_EQ(recorded.code, 0) << recorded.err;
  const nlohmann::json stats = nlohmann::json::parse(last_line(cli("stats tower --json").out));
  const nlohmann::json summary = check(mcap);
  EXPECT_EQ(summary["invalid"], nlohmann::json::array()) << "every message a valid foxglove.SceneUpdate";
  EXPECT_EQ(summary["schema_names"], nlohmann::json::array({"foxglove.SceneUpdate"}));
  EXPECT_EQ(summary["indexed_messages"], summary["messages"]) << "the indexed reader finds every message";
  EXPECT_EQ(summary["statistics_messages"], summary["messages"]);
  const nlohmann::json& roadmap = summary["topics"]["/ispars/tower/roadmap"];
  EXPECT_EQ(roadmap["spheres"], stats["vertices"]);
  EXPECT_EQ(roadmap["edges"], stats["edges"]);
  EXPECT_GE(roadmap["entities"].get<int>(), 1);
  const nlohmann::json& tour = summary["topics"]["/ispars/tower/tour"];
  ASSERT_EQ(tour["strips"].size(), 1u);
  EXPECT_GE(tour["strips"][0].size(), 2u) << "a closed tour through its stops";
  EXPECT_EQ(tour["strips"][0].front(), tour["strips"][0].back()) << "closed at the root";
  EXPECT_TRUE(test::mentions(recorded.out, "wrote " + std::to_string(summary["messages"].get<int>()) + " messages"))
      << recorded.out;

  // Bad input, refused by name; nothing is left at the path.
  const auto nowhere = dir_.path() / "nowhere" / "x.mcap";
  const CliRun bad_dir = cli("record tower --out " + nowhere.string() + " --until-idle");
  EXPECT_NE(bad_dir.code, 0);
  EXPECT_TRUE(test::mentions(bad_dir.err, "cannot write")) << bad_dir.err;
  EXPECT_EQ(cli("record tower --out x.mcap --tour -1").code, 2);
  const CliRun unknown = cli("record nothing_here --out " + (dir_.path() / "n.mcap").string());
  EXPECT_EQ(unknown.code, 1) << unknown.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "n.mcap"));
}

}  // namespace
}  // namespace ispars::test
