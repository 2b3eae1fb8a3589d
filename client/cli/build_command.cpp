// `ispars build`: a new roadmap for a scene, with the recipe's parameter overrides.

#include <fmt/format.h>

#include <cstdlib>

#include "cli_output.hpp"
#include "commands.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "whole_number.hpp"

namespace ispars::cli {
namespace {

class BuildCommand final : public Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("build", "build a new roadmap");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--method", args_.method, build_method_names())->required();
    cmd->add_option("--variant", args_.variant,
                     "spars, ispars: the rule set, " + spars_variant_names() + " (default stretch)");
    cmd->add_option("--samples", args_.samples, "samples to draw")
        ->required()
        ->check(whole_number(1, kMaxRequestSamples, "samples"));
    cmd->add_option("--seed", args_.seed, "random seed")->check(whole_number(0, kMaxSeed, ""));
    cmd->add_flag("--replace", args_.replace, "replace an existing roadmap");
    std::string set_help = "parameter override NAME=VALUE, one of:";
    for (const RecipeParameter& p : recipe_overrides()) set_help += fmt::format("\n    {}: {}; {}", p.name, p.doc, p.range);
    cmd->add_option("--set", sets_, set_help);
    cmd->add_flag("--wait", wait_, "follow progress until the build ends");
    cmd->add_flag("--json", json_, "print the final status as JSON");
    return cmd;
  }
  void check() override {
    // NAME=NUMBER each; the daemon checks the name and the value against the recipe.
    for (const std::string& s : sets_) {
      const auto eq = s.find('=');
      char* end = nullptr;
      const double value = eq == std::string::npos ? 0.0 : std::strtod(s.c_str() + eq + 1, &end);
      if (eq == std::string::npos || eq == 0 || end == s.c_str() + eq + 1 || *end != '\0') {
        throw CLI::ValidationError("--set", "'" + s + "' is not NAME=NUMBER");
      }
      args_.overrides[s.substr(0, eq)] = value;
    }
  }
  int run(client::Client& client) override {
    return follow_job(client, scene_, client.build(scene_, args_), wait_, json_);
  }

 private:
  std::string scene_;
  client::BuildArgs args_;
  std::vector<std::string> sets_;
  bool wait_ = false;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<Command> make_build_command() { return std::make_unique<BuildCommand>(); }

}  // namespace ispars::cli
