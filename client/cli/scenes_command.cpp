// `ispars scenes list | load | unload`.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"

namespace ispars::cli {
namespace {

class ScenesCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    scenes_ = app.add_subcommand("scenes", "list, load or unload scenes");
    scenes_->require_subcommand(1);
    list_ = scenes_->add_subcommand("list", "scenes of every daemon");
    list_->add_flag("--json", json_, "one JSON object");
    load_ = scenes_->add_subcommand("load", "load a scene (and its stored roadmap)");
    load_->add_option("scene", scene_, "scene name")->required();
    unload_ = scenes_->add_subcommand("unload", "unload a scene (its stored roadmap stays)");
    unload_->add_option("scene", scene_, "scene name")->required();
    return scenes_;
  }
  int run(client::Client& client) override {
    if (*list_) {
      print_list(client.list_scenes());
    } else if (*load_) {
      const auto r = client.load(scene_);
      std::cout << r.message << "\n";
      cli_app::print_status(r.status);
    } else {
      std::cout << client.unload(scene_).message << "\n";
    }
    return 0;
  }

 private:
  template <class Entries>
  void print_list(const Entries& entries) const {
    if (json_) {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& e : entries) {
        list.push_back({{"name", e.scene},
                        {"server_id", e.server_id},
                        {"loaded", e.loaded},
                        {"has_roadmap", e.has_roadmap},
                        {"note", e.note}});
      }
      std::cout << nlohmann::json{{"scenes", list}}.dump() << std::endl;
      return;
    }
    for (const auto& e : entries) {
      std::cout << fmt::format("{:<24} {:<28} {}{}{}\n", e.scene, e.server_id, e.loaded ? "loaded" : "-",
                               e.has_roadmap ? ", stored roadmap" : "", e.note.empty() ? "" : "\n    " + e.note);
    }
  }

  CLI::App* scenes_ = nullptr;
  CLI::App* list_ = nullptr;
  CLI::App* load_ = nullptr;
  CLI::App* unload_ = nullptr;
  std::string scene_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_scenes_command() { return std::make_unique<ScenesCommand>(); }

}  // namespace ispars::cli
