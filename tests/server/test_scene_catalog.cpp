// Scene names: only files inside the scene directory can ever be named.

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/scene_catalog.hpp"

#include <fstream>
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

TEST(SceneCatalog, NamesResolveInsideTheDirectoryOnly) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "scenes");
  const auto scenes = dir.path() / "scenes";
  std::ofstream(scenes / "tower.yaml") << "x: 1\n";
  std::ofstream(dir.path() / "outside.yaml") << "x: 1\n";
  std::filesystem::create_symlink(dir.path() / "outside.yaml", scenes / "escape.yaml");
  EXPECT_EQ(scene_file(scenes, "tower"), scenes / "tower.yaml");
  for (const std::string& bad : std::vector<std::string>{"../outside", "a/b", "", ".hidden", "tower\n", "to wer",
                                                         std::string(65, 'a'), "/etc/passwd", "..", "tower.yaml/.."}) {
    EXPECT_THROW((void)scene_file(scenes, bad), params::InputError) << bad;
  }
  try {
    (void)scene_file(scenes, "escape");
    FAIL();
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the scene directory"), std::string::npos) << e.what();
  }
  try {
    (void)scene_file(scenes, "missing");
    FAIL();
  } catch (const params::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "request: scene: no scene 'missing' in the daemon's scene directory");
  }
  const auto names = list_scene_names(scenes);
  EXPECT_EQ(names, (std::vector<std::string>{"escape", "tower"}));
}

TEST(SceneCatalog, ASceneFileNamesOnlyFilesInsideTheDirectory) {
  test::TempDir dir;
  const auto scenes = dir.path() / "scenes";
  std::filesystem::create_directories(scenes / "tower");
  const auto mesh = std::filesystem::path(ISPARS_SCENES_DIR) / "water_tower" / "water_tower.obj";
  std::filesystem::copy_file(mesh, scenes / "tower" / "tower.obj");
  std::filesystem::copy_file(mesh, dir.path() / "outside.obj");
  std::filesystem::create_symlink(dir.path() / "outside.obj", scenes / "link.obj");
  std::ofstream(dir.path() / "pois.txt") << "0 0 5\n";
  const std::string rest =
      "bounds: {min: [-15, -15, 0.5], max: [15, 15, 30]}\nrobot_radius: 0.5\nsensor_range: 6\n"
      "dense_delta: 2.0\nsparse_delta: 3.0\nstretch: 1.05\nroot: [10, 0, 2]\n";
  const auto write = [&](const std::string& name, const std::string& mesh_line, const std::string& pois) {
    std::ofstream(scenes / (name + ".yaml")) << mesh_line << "\n" << rest << "pois: " << pois << "\n";
  };
  write("inside", "mesh: tower/tower.obj", "{count: 10, seed: 1}");
  write("up", "mesh: ../outside.obj", "{count: 10, seed: 1}");
  write("absolute", "mesh: " + (dir.path() / "outside.obj").string(), "{count: 10, seed: 1}");
  write("symlink", "mesh: link.obj", "{count: 10, seed: 1}");
  write("poi_file", "mesh: tower/tower.obj", "{file: ../pois.txt}");
  EXPECT_EQ(load_scene_config(scenes, "inside").mesh.filename(), "tower.obj");
  for (const auto& [name, key] : std::vector<std::pair<std::string, std::string>>{
           {"up", "mesh"}, {"absolute", "mesh"}, {"symlink", "mesh"}, {"poi_file", "pois.file"}}) {
    try {
      (void)load_scene_config(scenes, name);
      ADD_FAILURE() << name << " was accepted";
    } catch (const params::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("request: scene: scene '" + name + "': " + key + " '"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("is outside the scene directory"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ispars::service
