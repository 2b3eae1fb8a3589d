// `ispars extend`: more samples for a scene's roadmap.

#include "cli_output.hpp"
#include "commands.hpp"

namespace ispars::cli {
namespace {

class ExtendCommand final : public Command {
 public:
  void add(CLI::App& app) override {
    cmd_ = app.add_subcommand("extend", "add samples to a roadmap");
    cmd_->add_option("scene", scene_, "scene name")->required();
    cmd_->add_option("--samples", samples_, "more samples")->required()->check(CLI::PositiveNumber);
    cmd_->add_flag("--wait", wait_, "follow progress until the extension ends");
    cmd_->add_flag("--json", json_, "print the final status as JSON");
  }
  [[nodiscard]] bool chosen() const override { return cmd_->parsed(); }
  int run(client::Client& client) override {
    return follow_job(client, scene_, client.extend(scene_, samples_), wait_, json_);
  }

 private:
  CLI::App* cmd_ = nullptr;
  std::string scene_;
  std::uint64_t samples_ = 0;
  bool wait_ = false;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<Command> make_extend_command() { return std::make_unique<ExtendCommand>(); }

}  // namespace ispars::cli
