// ispars-lab render, as a user runs it: a roadmap file, its dense pair and a tour drawn into a
// PNG whose counts match the files, a bounded subset said out loud, and bad input named.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/lab_cli_fixture.hpp"
#include "ispars/render/scene_render.hpp"

namespace {

using ispars::test::LabCli;
using ispars::test::LabRun;
using ispars::test::last_line;
using ispars::test::slurp;

class LabRender : public LabCli {
 protected:
  void SetUp() override {
    LabCli::SetUp();
    scene_ = std::string(ISPARS_SCENES_DIR) + "/demo_tank_tower.yaml";
    roadmap_ = (dir_ / "rm.json").string();
    tour_ = (dir_ / "tour.json").string();
    ASSERT_EQ(lab("build " + scene_ + " --method ispars --samples 1500 --out " + roadmap_).exit_code, 0);
    ASSERT_EQ(lab("tour " + roadmap_ + " --budget 2 --iterations 20 --bound simple --out " + tour_).exit_code, 0);
  }
  std::string scene_, roadmap_, tour_;
};

int count(const ispars::render::Image& image, bool (*is)(const std::uint8_t*)) {
  int n = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) n += is(image.pixel(x, y)) ? 1 : 0;
  }
  return n;
}

TEST_F(LabRender, DrawsTheRoadmapItsDensePairAndTheTourWithTheFilesCounts) {
  const auto png = dir_ / "pic.png";
  const LabRun run = lab("render " + scene_ + " --roadmap " + roadmap_ + " --dense --tour " + tour_ +
                         " --width 320 --height 240 --json --out " + png.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto json = nlohmann::json::parse(last_line(run.out));
  const auto file = nlohmann::json::parse(slurp(roadmap_));
  EXPECT_EQ(json["roadmap_edges"], file["graphs"]["roadmap"]["edges"].size());
  EXPECT_EQ(json["roadmap_edges_drawn"], json["roadmap_edges"]);
  EXPECT_EQ(json["dense_edges_drawn"], file["graphs"]["dense"]["edges"].size());
  EXPECT_EQ(json["tour_steps"].get<std::size_t>() + 1, nlohmann::json::parse(slurp(tour_))["positions"].size());
  const ispars::render::Image image = ispars::render::read_png(png.string());
  EXPECT_EQ(image.width, 320);
  EXPECT_EQ(image.height, 240);
  // The tour's orange and the roadmap's blue are both in the picture.
  EXPECT_GT(count(image, [](const std::uint8_t* p) { return p[0] > 200 && p[1] > 90 && p[1] < 170 && p[2] < 60; }), 50);
  EXPECT_GT(count(image, [](const std::uint8_t* p) { return p[2] > 150 && p[2] > p[0] + 60; }), 50);
}

TEST_F(LabRender, ARoadmapOverTheEdgeLimitIsDrawnAsASubsetAndSaysSo) {
  const LabRun run = lab("render " + scene_ + " --roadmap " + roadmap_ +
                         " --max-edges 5 --width 64 --height 48 --out " + (dir_ / "small.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("drew an evenly spread subset: 5 of"), std::string::npos) << run.out;
}

TEST_F(LabRender, BadInputIsNamed) {
  const std::string out = " --out " + (dir_ / "x.png").string();
  LabRun run = lab("render " + scene_ + " --dense" + out);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--dense"), std::string::npos) << run.err;
  const auto no_positions = write("bad_tour.json", R"({"walk": [0, 1, 0]})");
  run = lab("render " + scene_ + " --roadmap " + roadmap_ + " --tour " + no_positions.string() + out);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("positions"), std::string::npos) << run.err;
  run = lab("render " + scene_ + " --width 5" + out);
  EXPECT_EQ(run.exit_code, 2);
  run = lab("render " + scene_ + " --eye 1 2" + out);
  EXPECT_EQ(run.exit_code, 2);
  run = lab("render " + scene_ + " --out /nonexistent/dir/x.png");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("/nonexistent/dir/x.png"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));
}

}  // namespace
