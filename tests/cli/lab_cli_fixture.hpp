#pragma once
// The fixture of the ispars-lab command-line tests: runs the tool as a user does and captures
// its exit code, stdout and stderr.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ispars::test {

struct LabRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last line of a command's output: where --json puts its one object.
inline std::string last_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  if (end == std::string::npos) return {};
  const auto start = text.rfind('\n', end);
  const auto first = start == std::string::npos ? 0 : start + 1;
  return text.substr(first, end - first + 1);
}

class LabCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("ispars-cli-" + std::to_string(::getpid()) + "-" +
                                                     ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  LabRun lab(const std::string& args) const {
    const auto out = dir_ / "out.txt";
    const auto err = dir_ / "err.txt";
    const std::string command =
        std::string("'") + ISPARS_LAB + "' " + args + " >'" + out.string() + "' 2>'" + err.string() + "'";
    const int status = std::system(command.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
  }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }

  // A scene with the water tower mesh and one field replaced.
  std::filesystem::path tower_scene(const std::string& field_line) const {
    std::string text = std::string("mesh: ") + ISPARS_SCENES_DIR + "/water_tower/water_tower.obj\n" +
                       "bounds: {min: [-15, -15, 0.5], max: [15, 15, 30]}\nrobot_radius: 0.5\n"
                       "sensor_range: 6\ndense_delta: 2.0\nsparse_delta: 3.0\nstretch: 1.05\n"
                       "root: [10, 0, 2]\npois: {count: 50, seed: 7}\n";
    const std::string key = field_line.substr(0, field_line.find(':') + 1);
    const auto at = text.find(key);
    if (at != std::string::npos) text = text.substr(0, at) + field_line + text.substr(text.find('\n', at));
    return write("scene.yaml", text);
  }

  // Exit code 2, nothing on stdout, exactly one stderr line naming the file and the field.
  void expect_input_error(const LabRun& run, const std::string& file, const std::string& field) const {
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find(file + ": " + field + ": "), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty()) << run.out;
  }

  std::filesystem::path dir_;
};

}  // namespace ispars::test
