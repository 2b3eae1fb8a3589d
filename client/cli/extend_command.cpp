// `ispars extend`: more samples for a scene's roadmap.

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/params/cli_archive.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"

namespace ispars::cli {
namespace {

class ExtendCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("extend", "add samples to a roadmap");
    cmd->add_option("scene", scene_, "scene name")->required();
    params::add_flag(*cmd, kSamples, samples_)->required();
    cmd->add_flag("--wait", wait_, "follow progress until the extension ends");
    cmd->add_flag("--json", json_, "print the final status as JSON");
    return cmd;
  }
  int run(client::Client& client) override {
    return cli_app::follow_job(client, scene_, client.extend(scene_, samples_), wait_, json_);
  }

 private:
  std::string scene_;
  std::uint64_t samples_ = 0;
  bool wait_ = false;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_extend_command() { return std::make_unique<ExtendCommand>(); }

}  // namespace ispars::cli
