// The `ispars` command line against a real isparsd, as a user runs it: exit codes, one-line
// errors, JSON output, live replicas written to files; with the shipped localhost XML profile.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "integration/cli_fixture.hpp"
#include "ispars/render/scene_render.hpp"
#include "support/eventually.hpp"

namespace ispars::test {
namespace {

TEST_F(CliTest, NoDaemonExitsThreeNamingTheDomain) {
  const CliRun r = run("--domain " + std::to_string(domain_) + " --timeout 1.5 stats tower", dir_);
  EXPECT_EQ(r.code, 3);
  EXPECT_NE(r.err.find("no isparsd answered on DDS domain " + std::to_string(domain_)), std::string::npos) << r.err;
}

// A whole-number flag is read as typed and refused by name, with its range in its own unit, exit 2,
// before any daemon is asked (none runs here: a request would exit 3).
TEST_F(CliTest, BadCountsAreRefusedByNameWithTheirRange) {
  const std::string samples_range = "--samples: must be a whole number in [1, 9007199254740992], got ";
  for (const std::string value : {"0", "-5", "1e3", "99999999999999999999", "2.5", "0x10"}) {
    for (const std::string command : {"build tower --method ispars --samples=", "extend tower --samples="}) {
      const CliRun r = run(common_ + " " + command + value, dir_);
      EXPECT_EQ(r.code, 2) << command << value << ": " << r.err;
      EXPECT_NE(r.err.find(samples_range), std::string::npos) << command << value << ": " << r.err;
      EXPECT_EQ(r.err.find("1797"), std::string::npos) << r.err;
    }
  }
  const CliRun empty = run(common_ + " build tower --method ispars --samples=", dir_);
  EXPECT_EQ(empty.code, 2);
  EXPECT_NE(empty.err.find("--samples"), std::string::npos) << empty.err;
  const CliRun seed = run(common_ + " tour tower --budget 1 --seed=-1", dir_);
  EXPECT_EQ(seed.code, 2);
  EXPECT_NE(seed.err.find("--seed: must be a whole number in [0, 18446744073709551615], got -1"), std::string::npos)
      << seed.err;
  const CliRun targets = run(common_ + " tour tower --budget 1 --targets 3,1.5", dir_);
  EXPECT_EQ(targets.code, 2);
  EXPECT_NE(targets.err.find("--targets: must be a whole number in [0, 4294967295], got 1.5"), std::string::npos)
      << targets.err;
  const CliRun pois = run(common_ + " task add tower t --sample 1e3", dir_);
  EXPECT_EQ(pois.code, 2);
  EXPECT_NE(pois.err.find("--sample: must be a whole number in [1, 1000000], got 1e3"), std::string::npos) << pois.err;
  const CliRun domain = run("--domain 1e3 stats tower", dir_);
  EXPECT_EQ(domain.code, 2);
  EXPECT_NE(domain.err.find("--domain: must be a whole number in [0, 232], got 1e3"), std::string::npos) << domain.err;
  // The largest count is accepted by the CLI and then refused by the daemon's own limit (exit 3
  // here: no daemon answers).
  const std::string quick = "--domain " + std::to_string(domain_) + " --profile-file " + kProfile + " --timeout 0.5";
  EXPECT_EQ(run(quick + " extend tower --samples 9007199254740992", dir_).code, 3);
}

TEST_F(CliTest, BuildWatchSnapshotAndErrorsAsAUserSeesThem) {
  start();
  EXPECT_EQ(run(common_ + " scenes load tower", dir_).code, 0);
  // A build in flight, and a late-joining replica that follows it until the scene is idle.
  const CliRun started = run(common_ + " build tower --method ispars --samples 30000 --seed 4", dir_);
  ASSERT_EQ(started.code, 0) << started.err;
  const auto dump = dir_.path() / "replica.json";
  const std::string watch = std::string(ISPARS_CLI) + " " + common_ + " watch tower --until-idle --dump " +
                            dump.string() + " > " + (dir_.path() / "watch.txt").string() + " 2>&1 &";
  ASSERT_EQ(std::system(watch.c_str()), 0);
  nlohmann::json status;
  EXPECT_TRUE(test::eventually(
      [&] {
        const CliRun s = run(common_ + " stats tower --json", dir_);
        EXPECT_EQ(s.code, 0) << s.err;
        if (s.code != 0) return false;
        status = nlohmann::json::parse(last_line(s.out));
        return status["state"] == "idle";
      },
      std::chrono::seconds(120), "`ispars stats` says idle", std::chrono::milliseconds(200)));
  EXPECT_EQ(status["samples_done"], 30000);
  EXPECT_EQ(status["accepted_generation"], 0) << "an idle scene waits for no build";
  const CliRun stats = run(common_ + " stats tower --json", dir_);
  ASSERT_EQ(stats.code, 0);
  EXPECT_EQ(nlohmann::json::parse(last_line(stats.out))["vertices"], status["vertices"]);

  const auto snapshot = dir_.path() / "snapshot.json";
  ASSERT_EQ(run(common_ + " snapshot tower --out " + snapshot.string(), dir_).code, 0);
  // The watch writes its dump as it exits (not atomically): read until it is whole.
  const std::string expected = test::read_text(snapshot);
  EXPECT_TRUE(test::eventually([&] { return std::filesystem::exists(dump) && test::read_text(dump) == expected; },
                               std::chrono::seconds(30), "the live replica's dump equals the snapshot, byte for byte",
                               std::chrono::milliseconds(100)))
      << test::read_text(dir_.path() / "watch.txt");
  const auto file = nlohmann::json::parse(test::read_text(snapshot));
  EXPECT_EQ(file["graphs"]["roadmap"]["vertices"].size(), status["vertices"].get<std::size_t>());
  EXPECT_EQ(file["pois"].size(), status["poi_count"].get<std::size_t>());
  // For other tools: PLY and GraphML, chosen by the extension (Python's test_graphs reads both back).
  const auto ply = dir_.path() / "tower.ply", graphml = dir_.path() / "tower.graphml";
  ASSERT_EQ(run(common_ + " snapshot tower --out " + ply.string(), dir_).code, 0);
  ASSERT_EQ(run(common_ + " snapshot tower --out " + graphml.string(), dir_).code, 0);
  const std::string ply_text = test::read_text(ply), graphml_text = test::read_text(graphml);
  EXPECT_EQ(ply_text.rfind("ply\n", 0), 0u);
  EXPECT_TRUE(
      test::mentions(ply_text, "element vertex " + std::to_string(status["vertices"].get<std::size_t>()) + "\n"));
  EXPECT_TRUE(test::mentions(ply_text, "element edge " + std::to_string(status["edges"].get<std::size_t>()) + "\n"));
  std::size_t nodes = 0;
  for (std::size_t at = graphml_text.find("<node "); at != std::string::npos; at = graphml_text.find("<node ", at + 1))
    ++nodes;
  EXPECT_EQ(nodes, status["vertices"].get<std::size_t>());
  EXPECT_EQ(run(common_ + " snapshot tower --out x.obj --format obj", dir_).code, 2) << "an unknown format";
  const CliRun extend = run(common_ + " extend tower --samples 500 --wait --json", dir_);
  ASSERT_EQ(extend.code, 0) << extend.err;
  EXPECT_EQ(nlohmann::json::parse(last_line(extend.out))["samples_done"], 30500);
  EXPECT_EQ(nlohmann::json::parse(last_line(extend.out))["variant"], "stretch") << "the default rule set";
  EXPECT_EQ(nlohmann::json::parse(last_line(extend.out))["stretch_slack"], 0.0) << "no slack unless asked for";
  // --json, for a pipe: every line one JSON object, the replica as it changes, then its end.
  const CliRun watched = run(common_ + " watch tower --until-idle --json", dir_);
  ASSERT_EQ(watched.code, 0) << watched.err;
  std::vector<nlohmann::json> events;
  std::istringstream lines(watched.out);
  for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
  ASSERT_GE(events.size(), 2u) << watched.out;
  EXPECT_EQ(events.front()["event"], "replica");
  EXPECT_EQ(events.back()["event"], "end");
  EXPECT_EQ(events.back()["vertices"], nlohmann::json::parse(last_line(extend.out))["vertices"]);
  EXPECT_EQ(events.back()["retired"], false);
  EXPECT_EQ(events.back()["digest"].get<std::string>().size(), 16u);
  EXPECT_EQ(watched.err, "") << "no progress line with --json";

  // Errors: one line naming the problem, and the exit code of its kind.
  CliRun r = run(common_ + " build tower --method ispars --samples 100", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("request: replace: scene 'tower' already has a roadmap"), std::string::npos) << r.err;
  // What the typed request cannot hold, or a value outside its declared range, is refused before
  // anything is sent (exit 2); what depends on the scene, by the daemon (exit 1), in the same words.
  r = run(common_ + " build tower --method ispars --samples 100 --replace --set colour=1", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--set colour: unknown parameter (expected one of dense_delta, sparse_delta, stretch, "
                       "stretch_slack, stretch_slack_after, p_accept)"),
            std::string::npos)
      << r.err;
  r = run(common_ + " build tower --method ispars --samples 100 --replace --variant greedy", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--variant: 'greedy' is not one of stretch, alg1"), std::string::npos) << r.err;
  r = run(common_ + " build tower --method ispars --samples 100 --replace --set stretch=0.5", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--set stretch: must be in [1, 100], got 0.5"), std::string::npos) << r.err;
  r = run(common_ + " build tower --method dense --variant alg1 --samples 100 --replace", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("request: variant: 'alg1' given, but dense has no rule-set variants"), std::string::npos)
      << r.err;
  r = run(common_ + " build tower --method ispars --samples 100 --replace --set sparse_delta=100000", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("request: overrides.sparse_delta: 100000 is larger than the scene's diagonal"),
            std::string::npos)
      << r.err;
  r = run(common_ + " build tower --method ispars --samples 100 --set stretch", dir_);
  EXPECT_EQ(r.code, 2);
  r = run(common_ + " build tower --method ispars --samples -5", dir_);
  EXPECT_EQ(r.code, 2);
  r = run(common_ + " build tower --samples 5", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--method"), std::string::npos) << r.err;
  r = run(common_ + " stats nowhere", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("scene 'nowhere' is not loaded"), std::string::npos) << r.err;
  r = run(common_ + " path tower --from 0 0 nan --to 1 1 1", dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("path: from:"), std::string::npos) << r.err;
  r = run(common_ + " verify tower", dir_);
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("verified"), std::string::npos);
  // The rule set travels with the request into the recipe.
  r = run(common_ + " build tower --method spars --variant alg1 --samples 300 --replace --wait --json", dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(last_line(r.out))["variant"], "alg1");
  EXPECT_EQ(nlohmann::json::parse(last_line(r.out))["method"], "spars");
  EXPECT_EQ(daemon_->terminate(), 0) << daemon_->log();
}

// `ispars render`: the daemon's roadmap (its snapshot) and a tour it searches, drawn over the mesh
// of the user's copy of the scene file, which must be the daemon's scene.
TEST_F(CliTest, RenderDrawsTheDaemonsRoadmapAndTourOverTheLocalSceneFile) {
  start();
  ASSERT_EQ(run(common_ + " scenes load tower", dir_).code, 0);
  ASSERT_EQ(run(common_ + " build tower --method ispars --samples 3000 --seed 2 --wait", dir_).code, 0);
  const auto stats = nlohmann::json::parse(last_line(run(common_ + " stats tower --json", dir_).out));
  const auto png = dir_.path() / "tower.png";
  const std::string scene_file = (dir_.path() / "scenes" / "tower.yaml").string();
  CliRun r = run(
      common_ + " render tower --scene-file " + scene_file + " --tour 1 --width 320 --height 240 --out " + png.string(),
      dir_);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string edges = std::to_string(stats["edges"].get<std::size_t>());
  EXPECT_NE(r.out.find(edges + " of " + edges + " edges drawn, a tour of"), std::string::npos) << r.out;
  const render::Image image = render::read_png(png.string());
  EXPECT_EQ(image.width, 320);
  int orange = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const std::uint8_t* p = image.pixel(x, y);
      orange += p[0] > 200 && p[1] > 90 && p[1] < 170 && p[2] < 60 ? 1 : 0;
    }
  }
  EXPECT_GT(orange, 30) << "no tour in the picture";
  // Another scene's file is refused by name, and nothing is written.
  const auto other = dir_.path() / "other.yaml";
  std::ofstream(other) << "procedural: {kind: tank_tower, seed: 9}\n";
  const auto not_written = dir_.path() / "other.png";
  r = run(common_ + " render tower --scene-file " + other.string() + " --out " + not_written.string(), dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--scene-file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("is not the daemon's scene 'tower'"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(not_written));
  r = run(common_ + " render nowhere --scene-file " + scene_file + " --out " + not_written.string(), dir_);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("scene 'nowhere' is not loaded"), std::string::npos) << r.err;
  r = run(common_ + " render tower --scene-file " + scene_file + " --out /nonexistent/dir/x.png", dir_);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/nonexistent/dir/x.png"), std::string::npos) << r.err;
  EXPECT_EQ(daemon_->terminate(), 0) << daemon_->log();
}

}  // namespace
}  // namespace ispars::test
