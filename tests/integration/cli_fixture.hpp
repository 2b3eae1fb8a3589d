#pragma once
// Running the `ispars` command line against a real isparsd, as a user does: its exit code and
// output, and a fixture with a tank tower scene and a daemon on a domain of its own.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "ispars/local/local_daemon.hpp"
#include "support/test_support.hpp"

namespace ispars::test {

struct CliRun {
  int code = -1;
  std::string out;
  std::string err;
};

inline CliRun run(const std::string& args, const test::TempDir& dir) {
  const auto out = dir.path() / "stdout.txt";
  const auto err = dir.path() / "stderr.txt";
  const std::string command = std::string(ISPARS_CLI) + " " + args + " > " + out.string() + " 2> " + err.string();
  const int status = std::system(command.c_str());
  CliRun r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = test::read_text(out);
  r.err = test::read_text(err);
  return r;
}

inline std::string last_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  const auto start = text.rfind('\n', end);
  return text.substr(start == std::string::npos ? 0 : start + 1,
                     end - (start == std::string::npos ? 0 : start + 1) + 1);
}

class CliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    domain_ = local::random_domain();
    local::write_tank_tower_scenes(dir_.path() / "scenes", {"tower"});
    common_ = "--domain " + std::to_string(domain_) + " --profile-file " + kProfile + " --timeout 20";
  }
  void start() {
    daemon_ = std::make_unique<local::LocalDaemon>(ISPARS_DAEMON, domain_, dir_.path() / "data", dir_.path() / "scenes",
                                                   "cli", std::vector<std::string>{"--profile-file", kProfile});
  }
  const std::string kProfile = std::string(ISPARS_SOURCE_DIR) + "/deploy/fastdds_localhost.xml";
  test::TempDir dir_;
  int domain_ = 0;
  std::string common_;
  std::unique_ptr<local::LocalDaemon> daemon_;
};

}  // namespace ispars::test
