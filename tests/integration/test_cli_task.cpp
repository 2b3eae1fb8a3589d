// `ispars task` against a real isparsd: tasks added to a built roadmap (sampled, or from a file),
// listed with their coverage, verified, toured, followed by a live replica, kept across a
// restart, removed (durably, the roadmap unchanged); and the bad input a user can give, each
// refused by name.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <thread>

#include "integration/cli_fixture.hpp"

namespace ispars::test {
namespace {

nlohmann::json json_of(const CliRun& r) { return nlohmann::json::parse(last_line(r.out)); }

class CliTaskTest : public CliTest {
 protected:
  CliRun cli(const std::string& args) { return run(common_ + " " + args, dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const auto path = dir_.path() / name;
    std::ofstream(path) << text;
    return path.string();
  }
};

TEST_F(CliTaskTest, TasksAreAddedListedVerifiedTouredFollowedAndKeptAcrossARestart) {
  start();
  ASSERT_EQ(cli("scenes load tower").code, 0);
  CliRun r = cli("build tower --method ispars --samples 8000 --seed 4 --wait --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t base_pois = json_of(r)["poi_count"];
  const auto before = dir_.path() / "before.json";
  ASSERT_EQ(cli("snapshot tower --out " + before.string()).code, 0);

  r = cli("task add tower cracks --sample 40 --seed 5 --wait --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_of(r)["tasks"], 1);
  EXPECT_EQ(json_of(r)["poi_count"], base_pois + 40);
  EXPECT_EQ(json_of(r)["samples_done"], 8000) << "a task draws no samples";

  // A second task from a file (three of the scene's own POIs, which lie on the structure), with a
  // replica following from before it: the replica resyncs on the task's new POIs.
  const auto pois = nlohmann::json::parse(test::read_text(before))["pois"];
  std::string file = "# welds\n";
  for (int i = 0; i < 3; ++i)
    file += nlohmann::to_string(pois[i][0]) + " " + nlohmann::to_string(pois[i][1]) + " " +
            nlohmann::to_string(pois[i][2]) + "\n\n";
  const auto dump = dir_.path() / "replica.json";
  r = cli("task add tower welds --file " + write("welds.txt", file));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string watch = std::string(ISPARS_CLI) + " " + common_ + " watch tower --until-idle --dump " +
                            dump.string() + " > " + (dir_.path() / "watch.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(watch.c_str()), 0) << test::read_text(dir_.path() / "watch.txt");
  r = cli("stats tower --json");
  EXPECT_EQ(json_of(r)["tasks"], 2);
  const auto after = dir_.path() / "after.json";
  ASSERT_EQ(cli("snapshot tower --out " + after.string()).code, 0);
  EXPECT_EQ(test::read_text(dump), test::read_text(after)) << "the replica equals the snapshot, byte for byte";
  EXPECT_EQ(nlohmann::json::parse(test::read_text(after))["pois"].size(), base_pois + 43);

  r = cli("task list tower --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto tasks = json_of(r)["tasks"];
  ASSERT_EQ(tasks.size(), 2u);
  EXPECT_EQ(tasks[0]["name"], "cracks");
  EXPECT_EQ(tasks[0]["first_poi"], base_pois);
  EXPECT_EQ(tasks[1]["first_poi"], base_pois + 40);
  EXPECT_EQ(tasks[1]["poi_count"], 3);
  r = cli("verify tower");
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("verified"), std::string::npos) << r.out;
  r = cli("tour tower --task cracks --budget 1 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_of(r)["targets"], tasks[0]["pois_covered_root"]) << "the task's POIs seen from the root";
  EXPECT_EQ(json_of(r)["covered"], json_of(r)["targets"]);

  // Bad input: named, and nothing changes.
  r = cli("task add tower cracks --sample 5");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("task.name: a task 'cracks' exists already"), std::string::npos) << r.err;
  r = cli("task add tower far --file " + write("far.txt", "0 0 1000\n"));
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("task.pois[0]"), std::string::npos) << r.err;
  r = cli("task add tower bad --file " + write("bad.txt", "1 2 3\n4 five 6\n"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bad.txt:2: not three finite numbers"), std::string::npos) << r.err;
  r = cli("task add tower none --file " + (dir_.path() / "missing.txt").string());
  EXPECT_EQ(r.code, 2);
  r = cli("task add tower empty --file " + write("empty.txt", "# nothing\n"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no POIs in it"), std::string::npos) << r.err;
  r = cli("task add tower neither");
  EXPECT_EQ(r.code, 2);
  r = cli("task add tower many --sample 6000");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("task.sample"), std::string::npos) << r.err;
  r = cli("tour tower --task nope --budget 1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the roadmap has no task 'nope'"), std::string::npos) << r.err;
  EXPECT_EQ(json_of(cli("stats tower --json"))["tasks"], 2);
  const auto unchanged = dir_.path() / "unchanged.json";
  ASSERT_EQ(cli("snapshot tower --out " + unchanged.string()).code, 0);
  EXPECT_EQ(test::read_text(unchanged), test::read_text(after));

  // Renders over the user's scene file, whose POIs the daemon's begin with: every POI, or a task's.
  const std::string scene_file = (dir_.path() / "scenes" / "tower.yaml").string();
  const std::string small = " --width 160 --height 120 --scene-file " + scene_file;
  r = cli("render tower" + small + " --out " + (dir_.path() / "all.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
  r = cli("render tower" + small + " --task cracks --tour 1 --out " + (dir_.path() / "cracks.png").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("a tour of"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "cracks.png"));
  r = cli("render tower" + small + " --task nope --out " + (dir_.path() / "nope.png").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("has no task 'nope'"), std::string::npos) << r.err;

  // A restart recovers both tasks and the same roadmap.
  ASSERT_EQ(daemon_->terminate(), 0) << daemon_->log();
  start();
  ASSERT_EQ(cli("scenes load tower").code, 0);
  EXPECT_EQ(json_of(cli("task list tower --json"))["tasks"], tasks);
  const auto restarted = dir_.path() / "restarted.json";
  ASSERT_EQ(cli("snapshot tower --out " + restarted.string()).code, 0);
  EXPECT_EQ(test::read_text(restarted), test::read_text(after));

  // A removal: at once and durable; the roadmap is unchanged, the POIs leave every target set.
  r = cli("tour tower --budget 1 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const int all_targets = json_of(r)["targets"];
  r = cli("task remove tower welds");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("removed task 'welds' from the roadmap of 'tower'; 1 task left"), std::string::npos) << r.out;
  r = cli("tour tower --budget 1 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_of(r)["targets"], all_targets - tasks[1]["pois_covered_root"].get<int>())
      << "a default tour leaves the removed task's POIs out";
  r = cli("task remove tower welds");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("task: task 'welds' was removed already"), std::string::npos) << r.err;
  r = cli("task remove tower nope");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("the roadmap has no task 'nope'"), std::string::npos) << r.err;
  r = cli("tour tower --task welds --budget 1");
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("was removed already"), std::string::npos) << r.err;
  const auto removed = dir_.path() / "removed.json";
  ASSERT_EQ(cli("snapshot tower --out " + removed.string()).code, 0);
  EXPECT_EQ(test::read_text(removed), test::read_text(after)) << "a removal changes no vertex, edge or POI id";
  ASSERT_EQ(daemon_->terminate(), 0) << daemon_->log();
  start();
  ASSERT_EQ(cli("scenes load tower").code, 0);
  const auto left = json_of(cli("task list tower --json"))["tasks"];
  ASSERT_EQ(left.size(), 1u) << left;
  EXPECT_EQ(left[0], tasks[0]);
  EXPECT_EQ(json_of(cli("stats tower --json"))["tasks"], 1);
  EXPECT_EQ(daemon_->terminate(), 0) << daemon_->log();
}

}  // namespace
}  // namespace ispars::test
