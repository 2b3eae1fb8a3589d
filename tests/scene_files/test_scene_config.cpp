// The scene YAML contract: what parses, and a named error for each kind of bad input.

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/scene_config.hpp"

namespace ispars::scene_files {
namespace {

const std::string kValid = R"(
mesh: tower.obj
scale: 2.0
bounds: {min: [-15, -15, 0.5], max: [15, 15, 30]}
robot_radius: 0.5
sensor_range: 6
dense_delta: 2.0
sparse_delta: 3.0
stretch: 1.05
root: [10, 0, 2]
pois: {count: 300, seed: 7}
)";

SceneConfig parse(const std::string& text) { return parse_scene_config_text(text, "/scenes", "s.yaml"); }

// Replaces the line that starts with `key:` (or appends when absent).
std::string with(const std::string& key, const std::string& line) {
  std::string text = kValid;
  const auto at = text.find("\n" + key + ":");
  if (at == std::string::npos) return text + line + "\n";
  const auto end = text.find('\n', at + 1);
  return text.substr(0, at + 1) + line + text.substr(end);
}

std::string without(const std::string& key) { return with(key, ""); }

// Expects an InputError naming s.yaml and `field`; returns the message for further checks.
std::string expect_error(const std::string& text, const std::string& field) {
  try {
    (void)parse(text);
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.file(), "s.yaml");
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "not one line: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error for field " << field << " in:\n" << text;
  return {};
}

TEST(SceneConfig, ParsesTheContract) {
  const SceneConfig c = parse(kValid);
  EXPECT_EQ(c.mesh, std::filesystem::path("/scenes/tower.obj"));
  EXPECT_EQ(c.name, "s");
  EXPECT_DOUBLE_EQ(c.scale, 2.0);
  EXPECT_EQ(c.bounds.min, Vec3(-15, -15, 0.5));
  EXPECT_EQ(c.bounds.max, Vec3(15, 15, 30));
  EXPECT_DOUBLE_EQ(c.robot_radius, 0.5);
  EXPECT_DOUBLE_EQ(c.sensor_range, 6);
  EXPECT_DOUBLE_EQ(c.dense_delta, 2.0);
  EXPECT_DOUBLE_EQ(c.sparse_delta, 3.0);
  EXPECT_DOUBLE_EQ(c.stretch, 1.05);
  EXPECT_EQ(c.root, Vec3(10, 0, 2));
  EXPECT_EQ(c.pois.count, 300u);
  EXPECT_EQ(c.pois.seed, 7u);
  EXPECT_FALSE(c.pois.skip_ground);
  EXPECT_FALSE(c.procedural.has_value());
}

TEST(SceneConfig, ScaleIsOptionalAndPoisMayComeFromAFile) {
  const SceneConfig c =
      parse(with("pois", "pois: {file: p.txt, skip_ground: true}").replace(kValid.find("scale"), 11, ""));
  EXPECT_DOUBLE_EQ(c.scale, 1.0);
  EXPECT_EQ(c.pois.file, std::filesystem::path("/scenes/p.txt"));
}

TEST(SceneConfig, ProceduralScenesTakeGeneratorDefaultsAndOverrides) {
  const SceneConfig c = parse("procedural: {kind: tank_tower, seed: 3}\nrobot_radius: 0.4\n");
  ASSERT_TRUE(c.procedural.has_value());
  EXPECT_EQ(c.procedural->kind, "tank_tower");
  EXPECT_EQ(c.procedural->seed, 3u);
  EXPECT_DOUBLE_EQ(c.robot_radius, 0.4);
  EXPECT_GT(c.sensor_range, 0.0);
  expect_error("procedural: {kind: pyramid, seed: 3}\n", "procedural.kind");
  expect_error(kValid + "procedural: {kind: tank_tower, seed: 3}\n", "mesh");
}

TEST(SceneConfig, RadiusMustBePositiveAndFinite) {
  EXPECT_NE(expect_error(with("robot_radius", "robot_radius: -0.5"), "robot_radius")
                .find("must be in (0, 1000000], got -0.5"),
            std::string::npos);
  EXPECT_NE(expect_error(with("robot_radius", "robot_radius: .nan"), "robot_radius").find("finite"), std::string::npos);
  expect_error(with("robot_radius", "robot_radius: 0"), "robot_radius");
  expect_error(with("robot_radius", "robot_radius: .inf"), "robot_radius");
  expect_error(with("robot_radius", "robot_radius: half"), "robot_radius");
  expect_error(with("robot_radius", "robot_radius: [1, 2]"), "robot_radius");
}

TEST(SceneConfig, EveryNumericFieldIsChecked) {
  expect_error(with("sensor_range", "sensor_range: -6"), "sensor_range");
  expect_error(with("dense_delta", "dense_delta: 0"), "dense_delta");
  expect_error(with("sparse_delta", "sparse_delta: .nan"), "sparse_delta");
  expect_error(with("stretch", "stretch: 0.9"), "stretch");
  expect_error(with("scale", "scale: -1"), "scale");
  expect_error(with("pois", "pois: {count: 0, seed: 7}"), "pois.count");
  expect_error(with("pois", "pois: {count: -3, seed: 7}"), "pois.count");
  expect_error(with("pois", "pois: {count: 10, seed: x}"), "pois.seed");
  expect_error(with("pois", "pois: {count: 10}"), "pois.seed");
  expect_error(with("pois", "pois: {file: p.txt, count: 10}"), "pois.file");
  expect_error(with("pois", "pois: {count: 10, seed: 1, skip_ground: maybe}"), "pois.skip_ground");
}

// Every numeric parameter has an upper bound too (a scene 1000 km across, a stretch over 100: the
// range a build override has, one declaration for both).
TEST(SceneConfig, EveryNumericFieldHasAnUpperBound) {
  for (const std::string key : {"scale", "robot_radius", "sensor_range", "dense_delta", "sparse_delta"}) {
    EXPECT_NE(expect_error(with(key, key + ": 2e6"), key).find("must be in (0, 1000000], got 2000000"),
              std::string::npos)
        << key;
    EXPECT_NO_THROW((void)parse_scene_config_text(with(key, key + ": 1e6"), ".", "scene.yaml")) << key;
  }
  EXPECT_NE(expect_error(with("stretch", "stretch: 101"), "stretch").find("must be in [1, 100], got 101"),
            std::string::npos);
  EXPECT_NE(expect_error(with("stretch", "stretch: 0.9"), "stretch").find("must be in [1, 100], got 0.9"),
            std::string::npos);
}

TEST(SceneConfig, BoundsAndRootAreChecked) {
  expect_error(with("bounds", "bounds: {min: [0, 0, 0], max: [1, 1]}"), "bounds.max");
  expect_error(with("bounds", "bounds: {min: [0, 0, 5], max: [1, 1, 5]}"), "bounds");
  expect_error(with("bounds", "bounds: [0, 1]"), "bounds");
  expect_error(with("bounds", "bounds: {min: [0, 0, 0], max: [1, 1, 1], mid: [0, 0, 0]}"), "bounds.mid");
  const std::string message = expect_error(with("root", "root: [100, 0, 2]"), "root");
  EXPECT_NE(message.find("outside the bounds"), std::string::npos);
  expect_error(with("root", "root: [1, 2]"), "root");
  expect_error(with("root", "root: [1, .nan, 2]"), "root");
}

TEST(SceneConfig, MissingAndUnknownFieldsAreNamed) {
  for (const std::string key :
       {"bounds", "robot_radius", "sensor_range", "dense_delta", "sparse_delta", "stretch", "root", "pois"}) {
    EXPECT_NE(expect_error(without(key), key).find("missing"), std::string::npos);
  }
  expect_error(without("mesh"), "mesh");
  expect_error(kValid + "robot_radious: 0.5\n", "robot_radious");
  expect_error(kValid + "robot_radius: 0.6\n", "robot_radius");  // given twice
  expect_error(with("bounds", "bounds: {min: [0, 0, 0], max: [1, 1, 1], min: [0, 0, 0]}"), "bounds.min");
}

TEST(SceneConfig, MalformedYamlNamesTheLine) {
  const std::string message = expect_error("mesh: a.obj\nbounds: {min: [0, 0, 0]\nrobot_radius: 1\n", "yaml");
  EXPECT_NE(message.find("line"), std::string::npos);
  expect_error("- just\n- a list\n", "yaml");
  expect_error("", "yaml");
}

TEST(SceneConfig, MissingFileIsNamed) {
  try {
    (void)parse_scene_config("/nonexistent/scene.yaml");
    FAIL();
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/scene.yaml");
    EXPECT_EQ(e.field(), "file");
  }
}

}  // namespace
}  // namespace ispars::scene_files
