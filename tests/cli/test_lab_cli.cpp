// ispars-lab run as a user runs it: exit codes, one-line errors naming file and field, JSON.

#include <gtest/gtest.h>

#include <sstream>

#include <nlohmann/json.hpp>

#include "lab_cli_fixture.hpp"

namespace {

using ispars::test::LabCli;
using ispars::test::LabRun;
using ispars::test::last_line;
using ispars::test::slurp;

TEST_F(LabCli, SceneInfoJsonIsTheLastLine) {
  const LabRun run = lab(std::string("scene info ") + ISPARS_SCENES_DIR + "/water_tower.yaml --json --samples 500");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string last = run.out.substr(run.out.rfind('\n', run.out.size() - 2) + 1);
  const auto json = nlohmann::json::parse(last);
  EXPECT_EQ(json["triangles"], 1564);
  EXPECT_EQ(json["pois"], 300);
  EXPECT_EQ(json["samples"], 500);
  EXPECT_GT(json["pois_seen"].get<int>(), 200);
  EXPECT_NEAR(json["root_clearance"].get<double>(), 6.88, 0.01);
  EXPECT_GE(json["checks"]["point"].get<int>(), 500);
}

TEST_F(LabCli, SceneInfoIsDeterministic) {
  const std::string args =
      std::string("scene info ") + ISPARS_SCENES_DIR + "/truss_bridge.yaml --json --samples 300 --seed 4";
  auto strip_times = [](std::string s) {
    auto j = nlohmann::json::parse(s);
    j.erase("load_seconds");
    j.erase("sample_seconds");
    return j.dump();
  };
  EXPECT_EQ(strip_times(lab(args).out), strip_times(lab(args).out));
}

TEST_F(LabCli, BenchGeometryReportsAllPathsAndAgreement) {
  const LabRun run = lab(std::string("bench geometry ") + ISPARS_SCENES_DIR +
                         "/demo_tank_tower.yaml --json --queries 256 --reference-queries 20");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  for (const char* key : {"point_check_ns", "segment_check_ns", "chi_ns", "chi_near_structure_ns"}) {
    EXPECT_GT(json[key]["fast"].get<double>(), 0.0) << key;
    EXPECT_GT(json[key]["brute_force"].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(json["disagreements"]["point"], 0);
  EXPECT_EQ(json["disagreements"]["segment"], 0);
  EXPECT_EQ(json["disagreements"]["chi_pois"], 0);
  EXPECT_GT(json["rays_per_second"].get<double>(), 0.0);
}

TEST_F(LabCli, BenchTaskAddsATaskThatKeepsInvariantOneAndToursIt) {
  const LabRun run = lab(std::string("bench task ") + ISPARS_SCENES_DIR +
                         "/truss_bridge.yaml --samples 2000 --pois 40 --iterations 300 --verify --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string last = run.out.substr(run.out.rfind('\n', run.out.size() - 2) + 1);
  const auto json = nlohmann::json::parse(last);
  EXPECT_EQ(json["task_pois"], 40);
  EXPECT_EQ(json["verify"]["invariant_violations"], 0);
  EXPECT_TRUE(json["verify"]["geometry_ok"].get<bool>());
  EXPECT_GT(json["targets"].get<int>(), 0);
  EXPECT_GT(json["tour_added"].get<double>(), 0.0);
  EXPECT_GT(json["tour_rebuilt"].get<double>(), 0.0);
  EXPECT_GT(json["add_seconds"].get<double>(), 0.0);
}

TEST_F(LabCli, MissingSceneFile) {
  expect_input_error(lab("scene info " + (dir_ / "nope.yaml").string()), (dir_ / "nope.yaml").string(), "file");
}

TEST_F(LabCli, MissingMesh) {
  const auto yaml = tower_scene("mesh: gone.obj");
  const LabRun run = lab("scene info " + yaml.string());
  expect_input_error(run, (dir_ / "gone.obj").string(), "mesh");
}

TEST_F(LabCli, EmptyMesh) {
  write("empty.obj", "v 0 0 0\n");
  const auto yaml = tower_scene("mesh: empty.obj");
  expect_input_error(lab("scene info " + yaml.string()), (dir_ / "empty.obj").string(), "mesh");
}

TEST_F(LabCli, UnreadableMesh) {
  write("bad.obj", "f 1 2 3\nthis is not obj\n");
  const auto yaml = tower_scene("mesh: bad.obj");
  expect_input_error(lab("scene info " + yaml.string()), (dir_ / "bad.obj").string(), "mesh");
}

TEST_F(LabCli, NanRadius) {
  const auto yaml = tower_scene("robot_radius: .nan");
  expect_input_error(lab("scene info " + yaml.string()), yaml.string(), "robot_radius");
}

TEST_F(LabCli, NegativeRadius) {
  const auto yaml = tower_scene("robot_radius: -0.5");
  expect_input_error(lab("bench geometry " + yaml.string()), yaml.string(), "robot_radius");
}

TEST_F(LabCli, RootInCollision) {
  const auto yaml = tower_scene("root: [3, 3, 1]");  // 0.06 m from a leg
  expect_input_error(lab("scene info " + yaml.string()), yaml.string(), "root");
}

TEST_F(LabCli, RootOutsideBounds) {
  const auto yaml = tower_scene("root: [40, 0, 2]");
  expect_input_error(lab("scene info " + yaml.string()), yaml.string(), "root");
}

TEST_F(LabCli, MalformedYaml) {
  const auto yaml = write("scene.yaml", "mesh: [unclosed\nbounds: {\n");
  expect_input_error(lab("scene info " + yaml.string()), yaml.string(), "yaml");
}

TEST_F(LabCli, UsageErrorsExitTwo) {
  EXPECT_EQ(lab("").exit_code, 2);
  EXPECT_EQ(lab("scene info").exit_code, 2);
  EXPECT_EQ(lab("scene info x.yaml --samples 0").exit_code, 2);
  EXPECT_EQ(lab("frobnicate").exit_code, 2);
  EXPECT_EQ(lab("--help").exit_code, 0);
}

}  // namespace

namespace {

using ispars::test::LabCli;
using ispars::test::LabRun;
using ispars::test::last_line;
using ispars::test::slurp;

class LabBuild : public LabCli {};

TEST_F(LabBuild, JsonHasTheContractFields) {
  const LabRun run = lab(std::string("build ") + ISPARS_SCENES_DIR +
                         "/water_tower.yaml --method ispars --samples 1500 --seed 2 --verify --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["method"], "ispars");
  EXPECT_EQ(json["samples"], 1500);
  EXPECT_EQ(json["seed"], 2);
  EXPECT_GT(json["seconds"].get<double>(), 0.0);
  for (const char* graph : {"roadmap", "dense"}) {
    for (const char* key : {"vertices", "edges", "pois_covered", "pois_covered_root"}) {
      EXPECT_TRUE(json[graph].contains(key)) << graph << "." << key;
    }
  }
  EXPECT_LT(json["roadmap"]["vertices"].get<int>(), json["dense"]["vertices"].get<int>());
  EXPECT_GT(json["checks"]["segment"].get<int>(), 0);
  EXPECT_EQ(json["invariant_violations"], 0);
}

TEST_F(LabBuild, OutFilesAreByteIdenticalAcrossRunsAndThreadCounts) {
  const std::string base =
      std::string("build ") + ISPARS_SCENES_DIR + "/truss_bridge.yaml --method ispars --samples 2000 --seed 9 ";
  ASSERT_EQ(lab(base + "--threads 1 --out " + (dir_ / "a.json").string()).exit_code, 0);
  ASSERT_EQ(lab(base + "--threads 2 --out " + (dir_ / "b.json").string()).exit_code, 0);
  ASSERT_EQ(lab(base + "--threads 1 --out " + (dir_ / "c.json").string()).exit_code, 0);
  const std::string a = slurp(dir_ / "a.json");
  EXPECT_EQ(a, slurp(dir_ / "b.json"));
  EXPECT_EQ(a, slurp(dir_ / "c.json"));
  const auto json = nlohmann::json::parse(a);
  EXPECT_EQ(json["pois"].size(), 300u);
  EXPECT_EQ(json["root"], nlohmann::json::array({0, -12, 1.5}));
  const auto& g = json["graphs"]["roadmap"];
  EXPECT_EQ(g["vertices"].size(), g["visible"].size());
  EXPECT_EQ(g["vertices"][0], json["root"]);
  EXPECT_TRUE(json["graphs"].contains("dense"));
  for (const auto& e : g["edges"]) EXPECT_LT(e[0].get<std::size_t>(), g["vertices"].size());
}

TEST_F(LabBuild, IrisFilesFollowTheIrisFormat) {
  const std::string prefix = (dir_ / "wt").string();
  ASSERT_EQ(
      lab(std::string("build ") + ISPARS_SCENES_DIR + "/water_tower.yaml --method irisc --samples 800 --iris " + prefix)
          .exit_code,
      0);
  std::istringstream vertex(slurp(prefix + "_vertex"));
  std::istringstream edge(slurp(prefix + "_edge"));
  std::istringstream conf(slurp(prefix + "_conf"));
  std::string line;
  int vertices = 0;
  while (std::getline(vertex, line)) {
    std::istringstream f(line);
    int index = -1, time_vis = -1, time_build = -1;
    ASSERT_TRUE(f >> index >> time_vis >> time_build) << line;
    EXPECT_EQ(index, vertices++);
  }
  int confs = 0;
  while (std::getline(conf, line)) ++confs;
  EXPECT_EQ(confs, vertices);
  while (std::getline(edge, line)) {
    std::istringstream f(line);
    int u = -1, v = -1, checked = 0, valid = 0;
    double t1 = 0, t2 = 0, cost = -1;
    ASSERT_TRUE(f >> u >> v >> checked >> valid >> t1 >> t2 >> cost) << line;
    EXPECT_LT(u, vertices);
    EXPECT_LT(v, vertices);
    EXPECT_EQ(valid, 1);
    EXPECT_GT(cost, 0.0);
  }
}

TEST_F(LabBuild, BadArgumentsAreNamed) {
  const std::string scene = std::string(ISPARS_SCENES_DIR) + "/water_tower.yaml";
  EXPECT_EQ(lab("build " + scene + " --method prm --samples 10").exit_code, 2);
  EXPECT_EQ(lab("build " + scene + " --samples 10").exit_code, 2);  // --method is required
  EXPECT_EQ(lab("build " + scene + " --method dense --samples -5").exit_code, 2);
  const LabRun run = lab("build " + scene + " --method dense --samples 10 --out /nonexistent/dir/x.json");
  expect_input_error(run, "/nonexistent/dir/x.json", "--out");
}

}  // namespace

namespace {

using ispars::test::LabCli;
using ispars::test::LabRun;
using ispars::test::last_line;
using ispars::test::slurp;

class LabTour : public LabCli {};

TEST_F(LabTour, ToursOnRoadmapFilesAndIrisFilesKeepTheJsonContract) {
  const std::string scene = std::string(ISPARS_SCENES_DIR) + "/demo_tank_tower.yaml";
  const auto roadmap = dir_ / "rm.json";
  ASSERT_EQ(lab("build " + scene + " --method ispars --samples 3000 --out " + roadmap.string()).exit_code, 0);
  for (const char* graph : {"roadmap", "dense"}) {
    const LabRun run = lab("tour " + roadmap.string() + " --graph " + graph +
                           " --budget 2 --iterations 30 --json --out " + (dir_ / "tour.json").string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::string last = last_line(run.out);
    const auto json = nlohmann::json::parse(last);
    for (const char* key : {"cost", "covered", "targets", "seconds", "lower_bound", "valid", "trace"}) {
      EXPECT_TRUE(json.contains(key)) << key;
    }
    EXPECT_TRUE(json["valid"].get<bool>());
    EXPECT_EQ(json["covered"], json["targets"]);
    EXPECT_LE(json["lower_bound"].get<double>(), json["cost"].get<double>());
    ASSERT_FALSE(json["trace"].empty());
    EXPECT_DOUBLE_EQ(json["trace"].back()[1].get<double>(), json["cost"].get<double>());
    const auto tour = nlohmann::json::parse(slurp(dir_ / "tour.json"));
    EXPECT_EQ(tour["walk"].front(), 0);
    EXPECT_EQ(tour["walk"].back(), 0);
    EXPECT_EQ(tour["positions"].size(), tour["walk"].size());
  }
  // The same seed and iteration cap give the same tour.
  const std::string fixed = "tour " + roadmap.string() + " --budget 3 --iterations 20 --seed 4 --out ";
  ASSERT_EQ(lab(fixed + (dir_ / "a.json").string()).exit_code, 0);
  ASSERT_EQ(lab(fixed + (dir_ / "b.json").string()).exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "a.json"))["walk"],
            nlohmann::json::parse(slurp(dir_ / "b.json"))["walk"]);
  // With its scene, the tour is shortcut too: never longer, and what render draws ("path").
  const LabRun cut = lab("tour " + roadmap.string() + " --budget 2 --iterations 30 --json --scene " + scene +
                         " --out " + (dir_ / "cut.json").string());
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  const auto cut_json = nlohmann::json::parse(last_line(cut.out));
  EXPECT_GT(cut_json["shortcut_cost"].get<double>(), 0.0);
  EXPECT_LE(cut_json["shortcut_cost"].get<double>(), cut_json["cost"].get<double>());
  // The flown tour (what render draws, "path") is never longer than the walk's shortcut.
  EXPECT_LE(cut_json["flown_cost"].get<double>(), cut_json["shortcut_cost"].get<double>() * (1.0 + 1e-9));
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "cut.json"))["path"].size(),
            cut_json["flown_steps"].get<std::size_t>() + 1);
  EXPECT_FALSE(cut_json["stages"].empty());
  const LabRun other = lab("tour " + roadmap.string() + " --budget 1 --iterations 5 --scene " +
                           std::string(ISPARS_SCENES_DIR) + "/demo_truss_bridge.yaml");
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.err.find("--scene: its root is not the roadmap's root"), std::string::npos) << other.err;
  // IRIS files: all edges or valid ones only.
  const std::string prefix = (dir_ / "wt").string();
  ASSERT_EQ(lab("build " + scene + " --method irisc --samples 3000 --iris " + prefix).exit_code, 0);
  EXPECT_EQ(lab("tour --iris " + prefix + " --budget 1 --iterations 10 --json").exit_code, 0);
  EXPECT_EQ(lab("tour --iris " + prefix + " --all-edges --budget 1 --iterations 10 --json").exit_code, 0);
}

TEST_F(LabTour, ATargetsFileFixesTheTargetSetAndTheLpBoundStaysBelowTheTour) {
  const std::string scene = std::string(ISPARS_SCENES_DIR) + "/demo_tank_tower.yaml";
  const auto roadmap = dir_ / "rm.json";
  ASSERT_EQ(lab("build " + scene + " --method ispars --samples 1500 --out " + roadmap.string()).exit_code, 0);
  ASSERT_EQ(
      lab("tour " + roadmap.string() + " --budget 5 --iterations 20 --out " + (dir_ / "all.json").string()).exit_code,
      0);
  const auto all = nlohmann::json::parse(slurp(dir_ / "all.json"))["targets"];
  ASSERT_GE(all.size(), 3u);
  const auto targets = write("targets.txt", "# three of them\n" + all[0].dump() + " " + all[2].dump() + "\n\n" +
                                                all[1].dump() + "  # the second\n");
  const LabRun run = lab("tour " + roadmap.string() + " --targets " + targets.string() +
                         " --bound lp --budget 5 --iterations 50 --json --out " + (dir_ / "some.json").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(last_line(run.out));
  EXPECT_EQ(json["targets"], 3);
  EXPECT_EQ(json["covered"], 3);
  EXPECT_TRUE(json["valid"].get<bool>());
  const auto chosen = nlohmann::json::parse(slurp(dir_ / "some.json"))["targets"];
  EXPECT_EQ(chosen, (nlohmann::json{all[0], all[1], all[2]}));
  ASSERT_FALSE(json["bound_trace"].empty()) << "an LP bound was proven";
  EXPECT_GT(json["lower_bound"].get<double>(), 0.0);
  EXPECT_LE(json["lower_bound"].get<double>(), json["cost"].get<double>() * (1 + 1e-9));
  for (const auto& step : json["bound_trace"])
    EXPECT_LE(step[1].get<double>(), json["lower_bound"].get<double>() + 1e-9);

  const auto bad = write("bad.txt", "1 2\n3 x7\n");
  expect_input_error(lab("tour " + roadmap.string() + " --targets " + bad.string() + " --budget 1"), bad.string(),
                     "line 2");
  const auto negative = write("negative.txt", "-4\n");
  expect_input_error(lab("tour " + roadmap.string() + " --targets " + negative.string() + " --budget 1"),
                     negative.string(), "line 1");
  const auto empty = write("empty.txt", "# nothing\n");
  expect_input_error(lab("tour " + roadmap.string() + " --targets " + empty.string() + " --budget 1"), empty.string(),
                     "--targets");
  const auto unknown = write("unknown.txt", "0 4000000\n");
  const LabRun far = lab("tour " + roadmap.string() + " --targets " + unknown.string() + " --budget 1");
  expect_input_error(far, "tour", "targets");
  EXPECT_NE(far.err.find("unknown POI ids (the first: 4000000"), std::string::npos) << far.err;
  expect_input_error(lab("tour " + roadmap.string() + " --targets " + (dir_ / "none.txt").string() + " --budget 1"),
                     (dir_ / "none.txt").string(), "--targets");
}

TEST_F(LabTour, BadInputIsNamed) {
  expect_input_error(lab("tour " + (dir_ / "missing.json").string() + " --budget 1"), (dir_ / "missing.json").string(),
                     "file");
  const auto broken =
      write("broken.json", "{\"graphs\": {\"roadmap\": {\"vertices\": [[0,0,0]], \"visible\": [], \"edges\": []}}}");
  expect_input_error(lab("tour " + broken.string() + " --budget 1"), broken.string(), "graphs.roadmap.visible");
  const auto no_dense =
      write("nodense.json", "{\"graphs\": {\"roadmap\": {\"vertices\": [], \"visible\": [], \"edges\": []}}}");
  expect_input_error(lab("tour " + no_dense.string() + " --graph dense --budget 1"), no_dense.string(), "graphs.dense");
  const auto lonely = write("lonely.json",
                            "{\"pois\": [[0,0,0]], \"graphs\": {\"roadmap\": {\"vertices\": [[0,0,0],[1,0,0]], "
                            "\"visible\": [[],[0]], \"edges\": []}}}");
  expect_input_error(lab("tour " + lonely.string() + " --budget 1"), "tour", "root");
  write("x_vertex", "0 0 0 1 2\n1 0 0 x\n");
  write("x_edge", "0 1 1 1 0 0 1.5\n");
  expect_input_error(lab("tour --iris " + (dir_ / "x").string() + " --budget 1"), (dir_ / "x_vertex").string(),
                     "line 2");
  EXPECT_EQ(lab("tour --budget 1").exit_code, 2);                                   // no input
  EXPECT_EQ(lab("tour " + lonely.string() + " --iris x --budget 1").exit_code, 2);  // two inputs
  EXPECT_EQ(lab("tour " + lonely.string() + " --budget -1").exit_code, 2);
}

}  // namespace
