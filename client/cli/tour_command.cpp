// `ispars tour`: an inspection tour searched by the daemon, with live progress on stderr; the
// roadmap walk, its shortcut (the path as flown) and the proven bound.

#include <fmt/format.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <iostream>
#include <limits>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/cli_app/whole_number.hpp"

namespace ispars::cli {
namespace {

// [t0, v0, t1, v1, ...] as [[t0, v0], [t1, v1], ...].
template <class Flat>
nlohmann::json pairs(const Flat& flat) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i + 1 < flat.size(); i += 2) out.push_back({flat[i], flat[i + 1]});
  return out;
}

template <class Points>
nlohmann::json points_json(const Points& points) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : points) out.push_back({p.x(), p.y(), p.z()});
  return out;
}

std::size_t steps(std::size_t stops) { return stops == 0 ? 0 : stops - 1; }

nlohmann::json stages_json(const std::vector<client::TourStage>& stages) {
  nlohmann::json out = nlohmann::json::array();
  for (const client::TourStage& s : stages)
    out.push_back({{"stage", s.name}, {"cost", s.cost}, {"seconds", s.seconds}});
  return out;
}

nlohmann::json tour_json(const client::Tour& r) {
  return {{"cost", r.cost},
          {"covered", r.covered},
          {"targets", r.target_count},
          {"seconds", r.trace.empty() ? 0.0 : r.trace[r.trace.size() - 2]},
          {"lower_bound", r.lower_bound},
          {"valid", r.valid},
          {"trace", pairs(r.trace)},
          {"bound_trace", pairs(r.bound_trace)},
          {"bound_complete", r.bound_complete},
          {"walk_steps", steps(r.walk.size())},
          {"shortcut_cost", r.shortcut_cost},
          {"shortcut_steps", steps(r.shortcut_stops.size())},
          {"flown_cost", r.flown_cost},
          {"flown_steps", steps(r.flown_path.size())},
          {"stages", stages_json(r.stages)},
          {"graph_vertices", r.graph_vertices},
          {"graph_edges", r.graph_edges},
          {"version", r.version}};
}

void print_tour(const client::TourReply& reply) {
  const client::Tour& r = reply.tour;
  std::cout << reply.message << "\n";
  std::cout << fmt::format("  flown: {:.6g} in {} straight steps (the roadmap walk {:.6g}, shortcut {:.6g})\n",
                           r.flown_cost, steps(r.flown_path.size()), r.cost, r.shortcut_cost);
  std::string stages;
  for (const client::TourStage& s : r.stages)
    stages += fmt::format("{}{} {:.6g} at {:.2f} s", stages.empty() ? "" : ", ", s.name, s.cost, s.seconds);
  std::cout << "  stages: " << stages << "\n";
  std::cout << fmt::format("  searched last on {} vertices and {} edges\n", r.graph_vertices, r.graph_edges);
  std::cout << fmt::format("  {} roadmap steps, proven lower bound {:.6g} (gap {:.1f}%{}), {}\n", steps(r.walk.size()),
                           r.lower_bound, r.cost > 0 ? 100.0 * (r.cost - r.lower_bound) / r.cost : 0.0,
                           r.bound_complete ? ", LP solved over all its cuts" : "", r.valid ? "valid" : "NOT valid");
}

class TourCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("tour", "an inspection tour on the scene's roadmap, searched by the daemon");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--budget", budget_, "seconds of search")->required()->check(CLI::Range(0.001, 3600.0));
    cmd->add_option("--seed", seed_, "search seed")->check(cli_app::whole_number(0, cli_app::kMaxSeed));
    cmd->add_option("--targets", targets_, "POI ids to see (default: every POI seen from the root's component)")
        ->delimiter(',')
        ->check(cli_app::whole_number(0, std::numeric_limits<std::uint32_t>::max()));
    cmd->add_option("--task", task_,
                    "the POIs of this inspection task (ispars task list) seen from the root's component")
        ->excludes("--targets");
    cmd->add_flag("--json", json_, "one JSON object");
    cmd->add_option("--out", out_, "write the tour (walk, positions, trace) as JSON");
    return cmd;
  }
  int run(client::Client& client) override {
    const bool tty = ::isatty(STDERR_FILENO) != 0;
    const auto progress = [&](double t, double cost, double bound) {
      if (json_) return;
      std::cerr << fmt::format("{}{:8.2f} s  best tour {:.6g}  proven bound {:.6g}{}", tty ? "\r" : "", t, cost, bound,
                               tty ? "   " : "\n")
                << std::flush;
    };
    const auto reply = task_.empty() ? client.tour(scene_, budget_, seed_, targets_, progress)
                                     : client.task_tour(scene_, task_, budget_, seed_, progress);
    if (tty && !json_) std::cerr << "\n";
    const client::Tour& r = reply.tour;
    const nlohmann::json result = tour_json(r);
    if (!out_.empty()) {
      nlohmann::json file = result;
      file["walk"] = r.walk;
      file["positions"] = points_json(r.waypoints);
      file["path"] = points_json(r.flown_path);  // the flown tour: what render draws
      file["flown_sees"] = r.flown_sees;
      cli_app::write_text(out_, file.dump() + "\n");
    }
    if (json_) {
      std::cout << result.dump() << std::endl;
    } else {
      print_tour(reply);
    }
    return r.valid ? 0 : 1;
  }

 private:
  std::string scene_, out_, task_;
  double budget_ = 10;
  std::uint64_t seed_ = 1;
  std::vector<std::uint32_t> targets_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_tour_command() { return std::make_unique<TourCommand>(); }

}  // namespace ispars::cli
