// `ispars path`: a shortest path through a scene's roadmap between two points.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <iostream>

#include "commands.hpp"

namespace ispars::cli {
namespace {

class PathCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("path", "shortest path through the roadmap");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--from", from_, "start X Y Z")->required()->expected(3);
    cmd->add_option("--to", to_, "goal X Y Z")->required()->expected(3);
    cmd->add_flag("--json", json_, "one JSON object");
    return cmd;
  }
  int run(client::Client& client) override {
    const auto reply = client.path(scene_, {from_[0], from_[1], from_[2]}, {to_[0], to_[1], to_[2]});
    const client::Path& r = reply.path;
    if (json_) {
      nlohmann::json points = nlohmann::json::array();
      for (const auto& p : r.waypoints) points.push_back({p.x(), p.y(), p.z()});
      std::cout << nlohmann::json{{"scene", scene_}, {"length", r.length}, {"waypoints", points}}.dump() << std::endl;
      return 0;
    }
    std::cout << fmt::format("path of length {:.3f} through {} waypoints\n", r.length, r.waypoints.size());
    for (const auto& p : r.waypoints) std::cout << fmt::format("  {:.3f} {:.3f} {:.3f}\n", p.x(), p.y(), p.z());
    return 0;
  }

 private:
  std::string scene_;
  std::vector<double> from_, to_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_path_command() { return std::make_unique<PathCommand>(); }

}  // namespace ispars::cli
