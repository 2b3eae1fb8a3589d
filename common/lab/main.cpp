// ispars-lab: offline tools over the ispars core library. Each subcommand declares its flags and
// runs in a file of its own (commands.hpp); this file builds the command tree and reports errors.

#include <exception>
#include <functional>
#include <iostream>
#include <vector>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::lab {
namespace {

// Every subcommand's options, and which to run once the command line is parsed.
struct Lab {
  SceneInfoOptions info;
  BenchGeometryOptions geometry;
  BenchBuildOptions bench_build;
  BenchTourOptions bench_tour;
  BenchTaskOptions bench_task;
  BuildCommandOptions build;
  ExperimentOptions table, scaling, spanner, anytime, ablation, flown;
  TourCommandOptions tour;
  RenderCommandOptions render;
  std::vector<std::pair<CLI::App*, std::function<int()>>> commands;

  void add(CLI::App& app) {
    auto* scene = app.add_subcommand("scene", "Scene files")->require_subcommand(1);
    on(add_scene_info_command(*scene, info), [this] { return run_scene_info(info); });
    auto* bench =
        app.add_subcommand("bench", "Benchmarks that print figures (JSON with --json)")->require_subcommand(1);
    on(add_bench_geometry_command(*bench, geometry), [this] { return run_bench_geometry(geometry); });
    on(add_bench_build_command(*bench, bench_build), [this] { return run_bench_build(bench_build); });
    on(add_bench_tour_command(*bench, bench_tour), [this] { return run_bench_tour(bench_tour); });
    on(add_bench_task_command(*bench, bench_task), [this] { return run_bench_task(bench_task); });
    on(add_build_command(app, build), [this] { return run_build(build); });
    auto* experiment = app.add_subcommand("experiment", "Reproduce the paper's experiments")->require_subcommand(1);
    on(add_experiment_table_command(*experiment, table), [this] { return run_experiment_table(table); });
    on(add_experiment_scaling_command(*experiment, scaling), [this] { return run_experiment_scaling(scaling); });
    on(add_experiment_spanner_command(*experiment, spanner), [this] { return run_experiment_spanner(spanner); });
    on(add_experiment_anytime_command(*experiment, anytime), [this] { return run_experiment_anytime(anytime); });
    on(add_experiment_ablation_command(*experiment, ablation), [this] { return run_experiment_ablation(ablation); });
    on(add_experiment_flown_command(*experiment, flown), [this] { return run_experiment_flown(flown); });
    on(add_tour_command(app, tour), [this] { return run_tour(tour); });
    on(add_render_command(app, render), [this] { return run_render(render); });
  }
  void on(CLI::App* command, std::function<int()> run) { commands.emplace_back(command, std::move(run)); }
  int run() const {
    for (const auto& [command, action] : commands) {
      if (command->parsed()) return action();
    }
    return 1;
  }
};

// Exit codes: 0 done, 1 an internal error, 2 bad arguments or input (named).
int run(int argc, char** argv) {
  CLI::App app{"ispars-lab: scene reports, geometry benchmarks and roadmap experiments"};
  app.require_subcommand(1);
  Lab lab;
  lab.add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "ispars-lab: " << e.what() << " (see --help)\n";
    return 2;
  }
  try {
    return lab.run();
  } catch (const params::InputError& e) {
    std::cerr << "ispars-lab: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ispars-lab: internal error: " << e.what() << '\n';
    return 1;
  }
}

}  // namespace
}  // namespace ispars::lab

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  return ispars::lab::run(argc, argv);
}
