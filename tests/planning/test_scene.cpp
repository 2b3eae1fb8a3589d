// Loading whole scenes: the shipped ones, and each kind of bad scene a user can write.

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/scene_files/procedural.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

TEST(Scene, ShippedScenesLoadWithTheDocumentedTriangleCountsAndClearances) {
  // Triangle counts and root clearances from deploy/scenes/SOURCES.md.
  const std::map<std::string, std::pair<std::size_t, double>> expected{{"water_tower", {1564, 7.38}},
                                                                       {"truss_bridge", {3404, 4.45}},
                                                                       {"caric_city", {70104, 11.94}},
                                                                       {"powerplant", {4693, 9.53}},
                                                                       {"radio_tower", {4892, 7.29}}};
  for (const auto& [name, facts] : expected) {
    const Scene& scene = test::shared_scene(name);
    EXPECT_EQ(scene.mesh().triangle_count(), facts.first) << name;
    EXPECT_NEAR(scene.collision().distance_to_surface(scene.config().root), facts.second, 0.006) << name;
    EXPECT_EQ(scene.pois().size(), scene.config().pois.count) << name;
  }
}

TEST(Scene, DemoScenesLoad) {
  for (const std::string kind : {"truss_bridge", "tank_tower", "city_grid"}) {
    const Scene scene = Scene::load(test::scenes_dir() / ("demo_" + kind + ".yaml"));
    EXPECT_EQ(scene.config().procedural->kind, kind);
    EXPECT_GT(scene.pois().size(), 0u);
  }
}

TEST(Scene, SameFileSamePois) {
  const Scene a = Scene::load(test::scenes_dir() / "water_tower.yaml");
  const Scene& b = test::shared_scene("water_tower");
  EXPECT_EQ(a.pois(), b.pois());
}

// A scene directory with a cube mesh and a YAML whose fields the test may change.
class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_files::TriangleMesh cube;
    scene_files::add_box(cube, Vec3(0, 0, 2), Vec3(1, 1, 1));
    std::ostringstream obj;
    scene_files::write_obj(cube, obj);
    dir_.write("cube.obj", obj.str());
  }

  std::filesystem::path scene_file(const std::string& extra_or_override) const {
    std::string text =
        "mesh: cube.obj\nbounds: {min: [-5, -5, 0.5], max: [5, 5, 6]}\nrobot_radius: 0.5\n"
        "sensor_range: 4\ndense_delta: 1\nsparse_delta: 1.5\nstretch: 1.05\nroot: [4, 0, 2]\n"
        "pois: {count: 50, seed: 1}\n";
    const auto key_end = extra_or_override.find(':');
    const std::string key = extra_or_override.substr(0, key_end + 1);
    const auto at = text.find(key);
    if (!key.empty() && at != std::string::npos) {
      text = text.substr(0, at) + extra_or_override + text.substr(text.find('\n', at));
    } else if (!key.empty()) {
      text += extra_or_override + "\n";
    }
    return dir_.write("scene.yaml", text);
  }

  void expect_error(const std::filesystem::path& yaml, const std::string& file, const std::string& field,
                    const std::string& fragment) const {
    try {
      (void)Scene::load(yaml);
      ADD_FAILURE() << "loaded";
    } catch (const params::InputError& e) {
      EXPECT_EQ(e.file(), file);
      EXPECT_EQ(e.field(), field);
      EXPECT_NE(e.problem().find(fragment), std::string::npos) << e.what();
    }
  }

  test::TempDir dir_;
};

TEST_F(SceneFiles, ValidSceneLoads) {
  const Scene scene = Scene::load(scene_file(""));
  EXPECT_EQ(scene.mesh().triangle_count(), 12u);
  EXPECT_TRUE(scene.point_valid(Vec3(4, 0, 2)));
  EXPECT_FALSE(scene.point_valid(Vec3(0, 0, 3.2)));
}

TEST_F(SceneFiles, RootInCollisionIsNamed) {
  const auto yaml = scene_file("root: [1.2, 0, 2]");
  expect_error(yaml, yaml.string(), "root", "in collision");
}

TEST_F(SceneFiles, RootOutsideBoundsIsNamed) {
  const auto yaml = scene_file("root: [4, 0, 0.2]");
  expect_error(yaml, yaml.string(), "root", "outside the bounds");
}

TEST_F(SceneFiles, MissingMeshIsNamed) {
  const auto yaml = scene_file("mesh: nowhere.obj");
  expect_error(yaml, (dir_.path() / "nowhere.obj").string(), "mesh", "does not exist");
}

TEST_F(SceneFiles, EmptyMeshIsNamed) {
  dir_.write("empty.obj", "# no faces\nv 0 0 0\n");
  const auto yaml = scene_file("mesh: empty.obj");
  expect_error(yaml, (dir_.path() / "empty.obj").string(), "mesh", "");
}

TEST_F(SceneFiles, UnreadableMeshIsNamed) {
  const auto mesh = dir_.write("corrupt.stl", std::string("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", 46));
  const auto yaml = scene_file("mesh: corrupt.stl");
  expect_error(yaml, mesh.string(), "mesh", "cannot read mesh");
}

TEST_F(SceneFiles, ScaleAppliesToTheMeshAboutTheOrigin) {
  const Scene scene = Scene::load(scene_file("scale: 2"));
  EXPECT_NEAR(scene.mesh().bounds().max.z(), 6.0, 1e-6);
  EXPECT_FALSE(scene.point_valid(Vec3(2.3, 0, 4)));  // 0.3 m beside the scaled wall at x = 2
}

TEST_F(SceneFiles, MissingPoiFileIsNamed) {
  const auto yaml = scene_file("pois: {file: p.txt}");
  expect_error(yaml, (dir_.path() / "p.txt").string(), "pois.file", "cannot open");
}

}  // namespace
}  // namespace ispars::planning
