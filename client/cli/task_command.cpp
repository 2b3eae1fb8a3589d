// `ispars task add | list | remove`: inspection tasks, named POI sets added to a scene's built roadmap.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/cli_app/whole_number.hpp"

namespace ispars::cli {
namespace {

// A POI file is small: at most the daemon's 5,000 POIs, a line each.
constexpr std::uintmax_t kMaxPoiFileBytes = 1 << 20;

// "x y z" per line; blank lines and '#' comments skipped. CLI::ValidationError names the line.
std::vector<Vec3> read_pois(const std::string& path) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw CLI::ValidationError("--file", fmt::format("{}: cannot be read ({})", path, ec.message()));
  if (size > kMaxPoiFileBytes) {
    throw CLI::ValidationError("--file",
                               fmt::format("{}: {} bytes; a POI file has at most {}", path, size, kMaxPoiFileBytes));
  }
  std::ifstream in(path);
  if (!in) throw CLI::ValidationError("--file", fmt::format("{}: cannot be opened", path));
  std::vector<Vec3> pois;
  std::string line;
  for (std::size_t n = 1; std::getline(in, line); ++n) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double x = 0, y = 0, z = 0;
    std::string extra;
    if (!(fields >> x >> y >> z) || (fields >> extra) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      throw CLI::ValidationError("--file", fmt::format("{}:{}: not three finite numbers \"x y z\"", path, n));
    }
    pois.emplace_back(x, y, z);
  }
  if (pois.empty()) throw CLI::ValidationError("--file", fmt::format("{}: no POIs in it", path));
  return pois;
}

class TaskCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    task_ = app.add_subcommand("task", "inspection tasks: named POIs added to a built roadmap");
    task_->require_subcommand(1);
    add_ = task_->add_subcommand("add", "add a task's POIs to the scene's roadmap (no rebuild)");
    add_->add_option("scene", scene_, "scene name")->required();
    add_->add_option("name", name_, "task name (1-64 of A-Z a-z 0-9 _ - .)")->required();
    auto* file = add_->add_option("--file", file_, "POIs on the structure, one \"x y z\" per line");
    auto* sample = add_->add_option("--sample", sample_, "sample this many POIs on the structure's surface instead")
                       ->check(cli_app::whole_number(1, 1'000'000));
    file->excludes(sample);
    add_->add_option("--seed", seed_, "seed of --sample")
        ->needs(sample)
        ->check(cli_app::whole_number(0, cli_app::kMaxSeed));
    add_->add_flag("--wait", wait_, "follow progress until the task is added");
    add_->add_flag("--json", json_, "print the final status as JSON");
    list_ = task_->add_subcommand("list", "the roadmap's tasks and how many of their POIs it sees");
    list_->add_option("scene", scene_, "scene name")->required();
    list_->add_flag("--json", json_, "one JSON object");
    remove_ = task_->add_subcommand("remove",
                                    "take a task's POIs out of every target set (the roadmap keeps its "
                                    "vertices); its name is free again");
    remove_->add_option("scene", scene_, "scene name")->required();
    remove_->add_option("name", name_, "task name")->required();
    return task_;
  }
  void check() override {
    if (*add_ && file_.empty() && sample_ == 0) throw CLI::ValidationError("task add", "give --file or --sample");
    if (*add_ && !file_.empty()) pois_ = read_pois(file_);
  }
  int run(client::Client& client) override {
    if (*list_) {
      print_tasks(client.tasks(scene_));
      return 0;
    }
    if (*remove_) {
      std::cout << client.remove_task(scene_, name_).message << "\n";
      return 0;
    }
    const client::Reply reply =
        pois_.empty() ? client.add_sampled_task(scene_, name_, sample_, seed_) : client.add_task(scene_, name_, pois_);
    return cli_app::follow_job(client, scene_, reply, wait_, json_);
  }

 private:
  void print_tasks(const std::vector<client::TaskEntry>& tasks) const {
    if (json_) {
      nlohmann::json list = nlohmann::json::array();
      for (const auto& t : tasks) {
        list.push_back({{"name", t.name},
                        {"first_poi", t.first_poi},
                        {"poi_count", t.poi_count},
                        {"pois_covered", t.pois_covered},
                        {"pois_covered_root", t.pois_covered_root}});
      }
      std::cout << nlohmann::json{{"scene", scene_}, {"tasks", list}}.dump() << std::endl;
      return;
    }
    if (tasks.empty()) std::cout << fmt::format("scene '{}' has no tasks\n", scene_);
    for (const auto& t : tasks) {
      std::cout << fmt::format("{:<24} POIs {}..{} ({}), {} seen, {} from the root's component\n", t.name, t.first_poi,
                               t.first_poi + t.poi_count - 1, t.poi_count, t.pois_covered, t.pois_covered_root);
    }
  }

  CLI::App* task_ = nullptr;
  CLI::App* add_ = nullptr;
  CLI::App* list_ = nullptr;
  CLI::App* remove_ = nullptr;
  std::string scene_, name_, file_;
  std::uint32_t sample_ = 0;
  std::uint64_t seed_ = 1;
  std::vector<Vec3> pois_;
  bool wait_ = false;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_task_command() { return std::make_unique<TaskCommand>(); }

}  // namespace ispars::cli
