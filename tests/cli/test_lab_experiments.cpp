// ispars-lab's rule-set options and the experiments that measure them (spanner, ablation, flown), run
// as a user runs them.

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <map>

#include "lab_cli_fixture.hpp"

namespace {

using ispars::test::LabCli;
using ispars::test::LabRun;

class LabVariants : public LabCli {};

nlohmann::json last_json_line(const std::string& out) {
  return nlohmann::json::parse(out.substr(out.rfind("\n{") + 1));
}

TEST_F(LabVariants, BuildTakesAVariantAndReportsEdgesByCause) {
  const std::string base =
      std::string("build ") + ISPARS_SCENES_DIR + "/truss_bridge.yaml --method ispars --samples 2000 --json";
  const LabRun ours = lab(base);
  const LabRun paper = lab(base + " --variant alg1");
  ASSERT_EQ(ours.exit_code, 0) << ours.err;
  ASSERT_EQ(paper.exit_code, 0) << paper.err;
  const auto a = nlohmann::json::parse(ours.out);
  const auto b = nlohmann::json::parse(paper.out);
  EXPECT_EQ(a["variant"], "stretch");
  EXPECT_EQ(b["variant"], "alg1");
  EXPECT_EQ(a["dense"], b["dense"]) << "the same samples make the same dense roadmap";
  EXPECT_NE(a["roadmap"], b["roadmap"]);
  // Every sparse edge is counted under exactly one cause.
  for (const auto* run : {&a, &b}) {
    std::size_t by_cause = 0;
    for (const auto& [cause, n] : (*run)["edges_by_cause"].items()) by_cause += n.get<std::size_t>();
    EXPECT_EQ(by_cause, (*run)["roadmap"]["edges"].get<std::size_t>());
  }
  EXPECT_GT(a["edges_by_cause"]["join"].get<int>(), 0);
  EXPECT_EQ(b["edges_by_cause"]["join"].get<int>(), 0);
  EXPECT_GT(b["edges_by_cause"]["shortcut"].get<int>(), 0);
  EXPECT_EQ(lab(base + " --variant greedy").exit_code, 2);
}

TEST_F(LabVariants, SpannerMeasuresShortPairsPerVariant) {
  const LabRun run = lab("experiment spanner --scene water_tower --samples 2000 --pois 60 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = last_json_line(run.out);
  ASSERT_EQ(json["spanner"].size(), 2u);
  for (const auto& r : json["spanner"]) {
    ASSERT_EQ(r["viewpoint_stretch"]["bins"].size(), 11u) << "one Delta each up to 10 Delta, then one to infinity";
    EXPECT_EQ(r["invariant_violations"], 0);
    EXPECT_TRUE(r["geometry_ok"].get<bool>());
    std::size_t by_cause = 0;
    for (const auto& [cause, n] : r["edges_by_cause"].items()) by_cause += n.get<std::size_t>();
    EXPECT_EQ(by_cause, r["edges"].get<std::size_t>()) << r["variant"];
    const auto& near = r["viewpoint_stretch"]["bins"][0]["vs_segment"];
    ASSERT_GT(near["pairs"].get<int>(), 0);
    // Sparse vertices within Delta that see each other: the default keeps them within t, always;
    // Alg. 1 read literally does not.
    if (r["variant"] == "stretch") {
      EXPECT_EQ(near["share_over_t"].get<double>(), 0.0);
      EXPECT_LE(near["max"].get<double>(), 1.05 + 1e-9);
    } else {
      EXPECT_EQ(r["variant"], "alg1");
      EXPECT_GT(near["share_over_t"].get<double>(), 0.0);
    }
  }
  EXPECT_LT(json["spanner"][0]["viewpoint_stretch"]["within_3_Delta"]["vs_dense"]["median"].get<double>(),
            json["spanner"][1]["viewpoint_stretch"]["within_3_Delta"]["vs_dense"]["median"].get<double>());
  // Far pairs too: every pair joined in G_d is in a bin, and the bins add up to all of them.
  for (const auto& r : json["spanner"]) {
    std::size_t pairs = 0;
    for (const auto& bin : r["viewpoint_stretch"]["bins"]) pairs += bin["vs_dense"]["pairs"].get<std::size_t>();
    EXPECT_EQ(pairs, r["viewpoint_stretch"]["all"]["vs_dense"]["pairs"].get<std::size_t>());
    EXPECT_GT(r["viewpoint_stretch"]["beyond_3_Delta"]["vs_dense"]["pairs"].get<std::size_t>(), 0u);
  }
  const LabRun spars =
      lab("experiment spanner --scene water_tower --samples 2000 --pois 60 --variants spars,stretch+shortcut --json");
  ASSERT_EQ(spars.exit_code, 0) << spars.err;
  const auto spars_json = last_json_line(spars.out);
  ASSERT_EQ(spars_json["spanner"].size(), 2u);
  EXPECT_GT(spars_json["spanner"][0]["invariant_violations"].get<int>(), 0) << "SPARS has no inspection test";
  EXPECT_GT(spars_json["spanner"][1]["edges_by_cause"]["shortcut"].get<int>(), 0);
  EXPECT_GT(spars_json["spanner"][1]["edges_by_cause"]["join"].get<int>(), 0);
  EXPECT_EQ(lab("experiment spanner --scene water_tower --variants stretch,greedy --samples 10").exit_code, 2);
  const LabRun no_n = lab("experiment spanner --scene water_tower");
  EXPECT_EQ(no_n.exit_code, 2);
  EXPECT_NE(no_n.err.find("--samples"), std::string::npos) << no_n.err;
  const LabRun unknown = lab("experiment spanner --scene radio_tower --calibrate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--scene"), std::string::npos) << unknown.err;
}

TEST_F(LabVariants, AblationComparesRuleSetsOnTheSameTargetsAndWork) {
  const LabRun run =
      lab("experiment ablation --scene water_tower --delta 2.348 --seeds 1 --iterations 50 "
          "--rule-sets alg1,stretch,stretch+nearest-witness --wide --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = last_json_line(run.out);
  ASSERT_EQ(json["summary"].size(), 6u);  // dense, irisc, dense-wide and the three rule sets
  for (const auto& row : json["summary"]) {
    EXPECT_GT(row["tour"].get<double>(), 0.0) << row["roadmap"];
    // Flown: the walk shortcut (never longer), as a ratio to Dense's and Dense-wide's flown tours.
    EXPECT_GT(row["flown"].get<double>(), 0.0) << row["roadmap"];
    EXPECT_LE(row["flown"].get<double>(), row["tour"].get<double>() + 1e-9) << row["roadmap"];
    if (row["roadmap"] == "dense") {
      EXPECT_DOUBLE_EQ(row["tour_over_dense"].get<double>(), 1.0);
      EXPECT_DOUBLE_EQ(row["flown_over_dense"].get<double>(), 1.0);
    } else if (row["roadmap"] == "dense-wide") {
      EXPECT_DOUBLE_EQ(row["flown_over_dense_wide"].get<double>(), 1.0);
      EXPECT_GT(row["edges"].get<double>(), 10.0 * json["summary"][0]["edges"].get<double>());
    } else if (row["roadmap"] != "irisc") {
      EXPECT_EQ(row["violations"], 0.0) << row["roadmap"];
    }
  }
  // The stretch rules' slack: recorded, and it changes the stretch roadmap (not Alg. 1's).
  const LabRun slack =
      lab("experiment ablation --scene water_tower --delta 2.348 --seeds 1 --iterations 50 "
          "--rule-sets alg1,stretch --stretch-slack 0.5 --json");
  ASSERT_EQ(slack.exit_code, 0) << slack.err;
  const auto slack_json = last_json_line(slack.out);
  EXPECT_EQ(slack_json["stretch_slack"], 0.5);
  EXPECT_EQ(slack_json["stretch_slack_after"], 0);
  const auto edges = [](const nlohmann::json& j, const std::string& name) {
    for (const auto& row : j["summary"]) {
      if (row["roadmap"] == name) return row["edges"].get<double>();
    }
    return -1.0;
  };
  EXPECT_LT(edges(slack_json, "stretch"), edges(json, "stretch"));
  EXPECT_EQ(edges(slack_json, "alg1"), edges(json, "alg1"));
  // From a sample past N on, the slack changes nothing.
  const LabRun late =
      lab("experiment ablation --scene water_tower --delta 2.348 --seeds 1 --iterations 50 "
          "--rule-sets stretch --stretch-slack 0.5 --stretch-slack-after 1000000 --json");
  ASSERT_EQ(late.exit_code, 0) << late.err;
  EXPECT_EQ(edges(last_json_line(late.out), "stretch"), edges(json, "stretch"));
  EXPECT_EQ(lab("experiment ablation --scene water_tower --delta 2.3 --stretch-slack 1.5").exit_code, 2);
  const LabRun bad = lab("experiment ablation --scene water_tower --delta 2.3 --rule-sets alg1+teleport");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--rule-sets: rule set 'alg1+teleport': unknown rule 'teleport'"), std::string::npos)
      << bad.err;
  EXPECT_EQ(lab("experiment ablation --scene water_tower --delta 2.3 --rule-sets greedy").exit_code, 2);
}

#ifdef ISPARS_OMPL_BENCH
// experiment flown: every row's flown tour passes its check and is never longer than its walk;
// the corridor from the dense pair's vertices and from the seed's stream drawn again are the same
// samples, so the same tour; --rows and --wide-from reproduce a row (equal work is deterministic).
TEST_F(LabVariants, FlownRowsPassTheirChecksAndTheCorridorSourcesAgree) {
  const LabRun run = lab("experiment flown --scene water_tower --seeds 1 --iterations 200 --equal-time 0.1 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = last_json_line(run.out);
  std::map<std::string, nlohmann::json> rows;
  for (const auto& r : json["runs"]) rows[r["row"].get<std::string>()] = r;
  ASSERT_EQ(rows.size(), 8u) << run.out;
  for (const auto& [name, r] : rows) {
    EXPECT_TRUE(r["check"].get<bool>()) << name;
    EXPECT_LE(r["shortcut_cost"].get<double>(), r["walk_cost"].get<double>() * (1.0 + 1e-9)) << name;
  }
  for (const char* name : {"ispars-flown", "ispars-flown/dense-samples", "ispars-flown/stream"}) {
    EXPECT_LE(rows[name]["shortcut_cost"].get<double>(), rows["ispars"]["shortcut_cost"].get<double>()) << name;
  }
  EXPECT_GT(rows["ispars-flown/dense-samples"]["corridor_samples"].get<std::size_t>(), 0u);
  EXPECT_EQ(rows["ispars-flown/dense-samples"]["shortcut_cost"], rows["ispars-flown/stream"]["shortcut_cost"]);
  EXPECT_EQ(rows["ispars-flown/dense-samples"]["edges"], rows["ispars-flown/stream"]["edges"]);
  EXPECT_NE(run.out.find("| water_tower | 0.1 |"), std::string::npos) << "the equal-time panel";

  const auto earlier = write("earlier.json", run.out);
  const LabRun one =
      lab("experiment flown --scene water_tower --seeds 1 --iterations 200 --rows ispars-flown "
          "--wide-from " +
          earlier.string() + " --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto again = last_json_line(one.out);
  ASSERT_EQ(again["runs"].size(), 1u);
  EXPECT_EQ(again["runs"][0]["shortcut_cost"], rows["ispars-flown"]["shortcut_cost"]);
  const double ratio =
      rows["ispars-flown"]["shortcut_cost"].get<double>() / rows["dense-wide"]["shortcut_cost"].get<double>();
  EXPECT_NE(one.out.find(fmt::format("{:.3f} [", ratio)), std::string::npos) << one.out;
  EXPECT_EQ(one.out.find("| water_tower | 0.1 |"), std::string::npos) << "no panel without dense-wide";

  const LabRun other_work =
      lab("experiment flown --scene water_tower --seeds 1 --iterations 300 --rows ispars "
          "--wide-from " +
          earlier.string());
  EXPECT_EQ(other_work.exit_code, 2);
  EXPECT_NE(other_work.err.find("ran 200 iterations, not 300"), std::string::npos) << other_work.err;
  const LabRun bad_row = lab("experiment flown --scene water_tower --seeds 1 --rows ispars,teleport");
  EXPECT_EQ(bad_row.exit_code, 2);
  EXPECT_NE(bad_row.err.find("--rows"), std::string::npos) << bad_row.err;
  EXPECT_NE(bad_row.err.find("teleport"), std::string::npos) << bad_row.err;
  EXPECT_EQ(lab("experiment flown --scene water_tower --seeds 1 --rows ispars --wide-from /nonexistent.json").exit_code,
            2);
}

TEST_F(LabVariants, OmplBenchTimesBothBuildersOnTheSameScene) {
  const std::string command = std::string("'") + ISPARS_OMPL_BENCH + "' " + ISPARS_SCENES_DIR +
                              "/water_tower.yaml --samples 400 --json > '" + (dir_ / "ompl.txt").string() + "' 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << ispars::test::slurp(dir_ / "ompl.txt");
  const auto json = last_json_line(ispars::test::slurp(dir_ / "ompl.txt"));
  const auto dense = json["ispars"]["stretch"]["dense_vertices"].get<unsigned>();
  EXPECT_EQ(json["ispars"]["alg1"]["dense_vertices"].get<unsigned>(), dense) << "the same samples";
  for (const char* checker : {"our_checker", "fcl"}) {
    const auto& run = json["ompl_spars"][checker];
    EXPECT_FALSE(run["capped"].get<bool>()) << checker;
    EXPECT_EQ(run["dense_vertices"].get<unsigned>(), dense) << checker << ": stopped at our dense count";
    EXPECT_GT(run["over_ispars"].get<double>(), 0.0);
  }
}
#endif

}  // namespace
