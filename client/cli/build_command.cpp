// `ispars build`: a new roadmap for a scene, with the recipe's parameter overrides.

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/params/cli_archive.hpp"
#include "ispars/roadmap/build_request.hpp"

namespace ispars::cli {
namespace {

class BuildCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("build", "build a new roadmap");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--method", method_, build_method_names())->required();
    cmd->add_option("--variant", variant_,
                    "spars, ispars: the rule set, " + spars_variant_names() + " (default stretch)");
    params::add_flag(*cmd, kSamples, args_.samples)->required();
    params::add_flag(*cmd, kSeed, args_.seed);
    cmd->add_flag("--replace", args_.replace, "replace an existing roadmap");
    cmd->add_option("--set", sets_, "parameter override NAME=VALUE, one of:" + params::help<RecipeOverrides>());
    cmd->add_flag("--wait", wait_, "follow progress until the build ends");
    cmd->add_flag("--json", json_, "print the final status as JSON");
    return cmd;
  }
  void check() override {
    try {
      set_method(args_, method_, variant_, "ispars build");
      for (const std::string& s : sets_) {  // NAME=VALUE each, read and checked as declared
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0) throw CLI::ValidationError("--set", "'" + s + "' is not NAME=VALUE");
        params::set_text(args_.overrides, s.substr(0, eq), s.substr(eq + 1), "--set");
      }
    } catch (const params::InputError& e) {
      throw CLI::ValidationError(e.file() == "--set" ? "--set " + e.field() : "--" + e.field(), e.problem());
    }
  }
  int run(client::Client& client) override {
    return cli_app::follow_job(client, scene_, client.build(scene_, args_), wait_, json_);
  }

 private:
  std::string scene_;
  std::string method_;
  std::string variant_;
  BuildRequest args_;
  std::vector<std::string> sets_;
  bool wait_ = false;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_build_command() { return std::make_unique<BuildCommand>(); }

}  // namespace ispars::cli
