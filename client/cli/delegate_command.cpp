// `ispars render` is done by `ispars-render`, a program beside `ispars`: drawing needs the scene's
// mesh (assimp) and rays (Embree), which `ispars`, a client that only talks to daemons, does not
// link. `ispars render ARGS` runs `ispars-render` with the same arguments, connection flags
// included, as git runs its git-* programs.

#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

#include "commands.hpp"

namespace ispars::cli {
namespace {

class DelegatedCommand final : public cli_app::Command {
 public:
  DelegatedCommand(std::string name, std::string program, std::string description)
      : name_(std::move(name)), program_(std::move(program)), description_(std::move(description)) {}

  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand(name_, fmt::format("{} (by {})", description_, program_));
    cmd->prefix_command();  // every argument after the name goes to the program as given
    cmd->set_help_flag();   // --help too
    return cmd;
  }

  int run(client::Client& /*client*/) override { return 1; }  // not reached: run_elsewhere does it

  std::optional<int> run_elsewhere(int argc, char** argv) override {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::string path = (self.parent_path() / program_).string();
    std::vector<char*> args(argv, argv + argc);
    args[0] = const_cast<char*>(path.c_str());
    args.push_back(nullptr);
    std::cout.flush();
    ::execv(path.c_str(), args.data());
    std::cerr << fmt::format("ispars: `{}` is done by {}, which could not be run from {}: {}\n", name_, program_, path,
                             std::strerror(errno));
    return 1;
  }

 private:
  std::string name_, program_, description_;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_render_delegate() {
  return std::make_unique<DelegatedCommand>("render", "ispars-render",
                                            "a PNG of the scene's roadmap as the daemon serves it, and a tour");
}

}  // namespace ispars::cli
