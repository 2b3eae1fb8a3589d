// `ispars-lab experiment flown`: tours as a drone flies them, from Inspection-SPARS's small
// roadmap through the flown-tour pipeline (flown_tour.hpp), against the strongest baseline,
// Dense-wide (the same samples joined within 2 Delta), with the same solver work. Per scene and
// seed, calibrated as Table II: the rows of flown_rows.hpp; then paired per-seed ratios to
// Dense-wide with 95% intervals, and an equal-time panel (the best flown tour at a few wall-clock
// budgets).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "flown_rows.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::lab {
namespace {

// Every figure of one row over the seeds of one scene.
struct RowRuns {
  std::vector<double> vertices, edges, walk, flown, seconds, over_wide, targets_lost;
  std::size_t checks_failed = 0;
};

std::string summary_row(const std::string& scene, const std::string& name, const RowRuns& r) {
  return fmt::format("| {} | {} | {:.0f} | {:.0f} | {} | {} | {} | {:.2f} | {} | {} |\n", scene, name,
                     mean_sd(r.vertices).mean, mean_sd(r.edges).mean, mean_sd_cell(r.walk, 2), mean_sd_cell(r.flown, 2),
                     ratio_interval_cell(r.over_wide), mean_sd(r.seconds).mean,
                     r.targets_lost.empty() ? std::string("0") : fmt::format("{:.1f}", mean_sd(r.targets_lost).mean),
                     r.checks_failed == 0 ? std::string("all") : fmt::format("{} FAILED", r.checks_failed));
}

// Dense-wide's flown tour per (scene, seed) from an earlier run's --json output, checked to have
// had `iterations` solver iterations (equal work makes it deterministic).
std::map<std::pair<std::string, std::uint64_t>, double> wide_tours_from(const std::string& path,
                                                                        std::uint64_t iterations) {
  std::map<std::pair<std::string, std::uint64_t>, double> out;
  if (path.empty()) return out;
  std::ifstream in(path);
  if (!in) throw params::InputError(path, "--wide-from", "cannot read it");
  nlohmann::json runs;
  std::string line;
  while (std::getline(in, line)) {  // the JSON is the output's last line
    if (!line.empty() && line.front() == '{') runs = nlohmann::json::parse(line, nullptr, false);
  }
  if (!runs.is_object() || !runs.contains("runs")) {
    throw params::InputError(path, "--wide-from", "holds no experiment flown --json output");
  }
  for (const auto& r : runs["runs"]) {
    if (r.value("row", "") != "dense-wide") continue;
    if (r.value("iterations", std::uint64_t{0}) != iterations) {
      throw params::InputError(path, "--wide-from",
                               fmt::format("{} seed {}: dense-wide ran {} iterations, not {}", r.value("scene", ""),
                                           r.value("seed", 0), r.value("iterations", 0), iterations));
    }
    out[{r.at("scene").get<std::string>(), r.at("seed").get<std::uint64_t>()}] = r.at("shortcut_cost").get<double>();
  }
  return out;
}

const FlownRow* find_row(const std::vector<FlownRow>& rows, const std::string& name) {
  for (const FlownRow& row : rows) {
    if (row.name == name) return &row;
  }
  return nullptr;
}

// The equal-time panel pits ispars-flown against Dense-wide: it runs when both rows do.
bool equal_time_panel(const ExperimentOptions& options) {
  const auto runs = [&](const char* name) {
    return options.rows.empty() || std::find(options.rows.begin(), options.rows.end(), name) != options.rows.end();
  };
  return runs("ispars-flown") && runs("dense-wide");
}

}  // namespace

int run_experiment_flown(const ExperimentOptions& options) {
  const SolverWork work{options.iterations, options.cap, options.jobs};
  for (const std::string& name : options.rows) {
    const auto& names = flown_row_names();
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      throw params::InputError("experiment flown", "--rows",
                               fmt::format("no row '{}' (rows: {})", name, fmt::join(names, ", ")));
    }
  }
  const auto earlier_wide = wide_tours_from(options.wide_from, options.iterations);
  std::cout << fmt::format(
      "# Flown tours: {} seeds, {} solver iterations per search, one solver thread each, {} rows "
      "at a time, {:.0f} s cap\n\n",
      options.seeds, work.iterations, work.jobs, work.cap_seconds);
  std::ostringstream summary, panel;
  summary << "| scene | row | \\|V\\| | \\|E\\| searched | roadmap walk | flown tour | flown / Dense-wide's flown "
             "(mean [95% CI], worst) | seconds | targets lost | checks passed "
             "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  panel << "| scene | budget [s] | ispars-flown | dense-wide | ratio (mean [95% CI], worst) |\n|---|---|---|---|---|\n";
  nlohmann::json results = nlohmann::json::array();
  for (const PaperSetting& ps : paper_settings()) {
    if (!options.only_scenes.empty() &&
        std::find(options.only_scenes.begin(), options.only_scenes.end(), ps.scene) == options.only_scenes.end()) {
      continue;
    }
    const scene_files::SceneConfig base =
        scene_files::parse_scene_config(options.scenes_dir + "/" + ps.scene + ".yaml");
    const double delta = calibrate_delta(base, ps.samples, ps.degree, options.threads);
    std::map<std::string, RowRuns> runs;
    std::map<double, std::pair<std::vector<double>, std::vector<double>>> timed;  // budget -> flown, wide
    std::vector<std::string> order;
    for (std::uint64_t seed = 1; seed <= options.seeds; ++seed) {
      const SeedRoadmaps roadmaps = build_seed_roadmaps(base, ps, seed, delta, options.threads);
      const std::vector<FlownRow> rows = flown_rows(roadmaps, work, seed, options.rows);
      const FlownRow* wide_row = find_row(rows, "dense-wide");
      const auto earlier = earlier_wide.find({ps.scene, seed});
      const double wide = wide_row != nullptr             ? wide_row->tour.cost
                          : earlier != earlier_wide.end() ? earlier->second
                                                          : std::nan("");
      for (const FlownRow& row : rows) {
        if (runs.find(row.name) == runs.end()) order.push_back(row.name);
        RowRuns& r = runs[row.name];
        r.vertices.push_back(static_cast<double>(row.vertices));
        r.edges.push_back(static_cast<double>(row.tour.graph_edges));
        r.walk.push_back(row.tour.walk_cost);
        r.flown.push_back(row.tour.cost);
        r.seconds.push_back(row.seconds);
        if (!std::isnan(wide)) r.over_wide.push_back(row.tour.cost / wide);
        r.targets_lost.push_back(static_cast<double>(row.targets_lost));
        r.checks_failed += row.tour.check.valid() ? 0 : 1;
        results.push_back(row_json(ps.scene, seed, row));
      }
      std::cerr << fmt::format("{} seed {}: dense-wide {:.2f}", ps.scene, seed, wide);
      for (const FlownRow& row : rows) std::cerr << fmt::format(", {} {:.2f}", row.name, row.tour.cost);
      std::cerr << '\n';
      for (const double budget : equal_time_panel(options) ? options.budgets : std::vector<double>{}) {
        const auto [flown, dense_wide] = equal_time(roadmaps, budget, seed);
        timed[budget].first.push_back(flown);
        timed[budget].second.push_back(dense_wide);
      }
    }
    for (const std::string& name : order) summary << summary_row(ps.scene, name, runs[name]);
    for (const auto& [budget, pair] : timed) panel << equal_time_row(ps.scene, budget, pair.first, pair.second);
  }
  std::cout << summary.str();
  if (equal_time_panel(options) && !options.budgets.empty()) {
    std::cout << "\nEqual time (wall clock, one solver thread; '-': no tour by then):\n\n" << panel.str();
  }
  if (options.json) std::cout << nlohmann::json{{"runs", results}}.dump() << std::endl;
  return 0;
}

CLI::App* add_experiment_flown_command(CLI::App& parent, ExperimentOptions& options) {
  auto* cmd =
      parent.add_subcommand("flown", "Flown tours: Inspection-SPARS through the tour pipeline against Dense-wide");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--seeds", options.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  cmd->add_option("--scene", options.only_scenes, "Only these scenes (water_tower, truss_bridge, caric_city)");
  cmd->add_option("--iterations", options.iterations, "Solver iterations per search: the same for every row")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  cmd->add_option("--cap", options.cap, "Wall-clock cap per row, seconds")->check(CLI::Range(0.1, 1e5));
  cmd->add_option("--jobs", options.jobs, "Rows at once (one solver thread each)")->check(CLI::Range(1u, 64u));
  cmd->add_option("--equal-time", options.budgets, "Wall-clock budgets of the equal-time panel, seconds")
      ->check(CLI::Range(0.01, 3600.0));
  cmd->add_option("--rows", options.rows, "Only these rows (default: every one)")->delimiter(',');
  cmd->add_option("--wide-from", options.wide_from,
                  "An earlier run's --json output: Dense-wide's flown tours when the dense-wide row is not run");
  return cmd;
}

}  // namespace ispars::lab
