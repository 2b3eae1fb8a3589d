// Scene names: only files inside the scene directory can ever be named.

#include <gtest/gtest.h>

#include "ispars/input_error.hpp"
#include "ispars/service/scene_catalog.hpp"

#include <fstream>
#include "support/test_support.hpp"

namespace ispars {
namespace {

TEST(SceneCatalog, NamesResolveInsideTheDirectoryOnly) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "scenes");
  const auto scenes = dir.path() / "scenes";
  std::ofstream(scenes / "tower.yaml") << "x: 1\n";
  std::ofstream(dir.path() / "outside.yaml") << "x: 1\n";
  std::filesystem::create_symlink(dir.path() / "outside.yaml", scenes / "escape.yaml");
  EXPECT_EQ(scene_file(scenes, "tower"), scenes / "tower.yaml");
  for (const std::string& bad : std::vector<std::string>{"../outside", "a/b", "", ".hidden", "tower\n", "to wer", std::string(65, 'a'),
                                "/etc/passwd", "..", "tower.yaml/.."}) {
    EXPECT_THROW((void)scene_file(scenes, bad), InputError) << bad;
  }
  try {
    (void)scene_file(scenes, "escape");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("outside the scene directory"), std::string::npos) << e.what();
  }
  try {
    (void)scene_file(scenes, "missing");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "request: scene: no scene 'missing' in the daemon's scene directory");
  }
  const auto names = list_scene_names(scenes);
  EXPECT_EQ(names, (std::vector<std::string>{"escape", "tower"}));
}

}  // namespace
}  // namespace ispars
