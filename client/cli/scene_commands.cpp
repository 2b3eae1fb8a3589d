// The one-request commands on a scene: `ispars cancel`, `stats`, `drop` and `verify`.

#include <functional>
#include <iostream>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"

namespace ispars::cli {
namespace {

// A command whose only argument is the scene (and maybe --json), run by `action`.
class SceneCommand final : public cli_app::Command {
 public:
  using Action = std::function<int(client::Client&, const std::string& scene, bool json)>;
  SceneCommand(std::string name, std::string help, bool has_json, Action action)
      : name_(std::move(name)), help_(std::move(help)), has_json_(has_json), action_(std::move(action)) {}
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand(name_, help_);
    cmd->add_option("scene", scene_, "scene name")->required();
    if (has_json_) cmd->add_flag("--json", json_, "one JSON object");
    return cmd;
  }
  int run(client::Client& client) override { return action_(client, scene_, json_); }

 private:
  std::string name_, help_;
  bool has_json_;
  Action action_;
  std::string scene_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_cancel_command() {
  return std::make_unique<SceneCommand>("cancel", "stop a running build after its current chunk", false,
                                        [](client::Client& c, const std::string& scene, bool) {
                                          std::cout << c.cancel(scene).message << "\n";
                                          return 0;
                                        });
}

std::unique_ptr<cli_app::Command> make_stats_command() {
  return std::make_unique<SceneCommand>("stats", "a scene's roadmap status", true,
                                        [](client::Client& c, const std::string& scene, bool json) {
                                          const client::SceneStatus s = c.stats(scene);
                                          if (json) {
                                            std::cout << cli_app::status_json(s).dump() << std::endl;
                                          } else {
                                            cli_app::print_status(s);
                                          }
                                          return 0;
                                        });
}

std::unique_ptr<cli_app::Command> make_drop_command() {
  return std::make_unique<SceneCommand>("drop", "delete a scene's roadmap", false,
                                        [](client::Client& c, const std::string& scene, bool) {
                                          std::cout << c.drop(scene).message << "\n";
                                          return 0;
                                        });
}

std::unique_ptr<cli_app::Command> make_verify_command() {
  return std::make_unique<SceneCommand>("verify", "check a roadmap (validity, costs, Invariant 1)", false,
                                        [](client::Client& c, const std::string& scene, bool) {
                                          const auto r = c.verify(scene);
                                          const std::uint64_t violations = r.verify.violations;
                                          std::cout << (violations == 0 ? "verified: " : "NOT verified: ") << r.message
                                                    << "\n";
                                          return violations == 0 ? 0 : 1;
                                        });
}

}  // namespace ispars::cli
