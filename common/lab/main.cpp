// ispars-lab: offline tools over the ispars core library.

#include <cstdio>
#include <exception>
#include <iostream>

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "commands.hpp"
#include "ispars/input_error.hpp"
#include "ispars/builders/roadmap_builder.hpp"
#include "ispars/roadmap/build_recipe.hpp"

namespace {

// --stretch-slack and --stretch-slack-after, with the recipe's own ranges.
void add_stretch_slack_options(CLI::App& command, double& slack, std::uint64_t& after) {
  command.add_option("--stretch-slack", slack, "Stretch rules: additive slack of the bounds, a fraction of Delta (default 0)")
      ->check(CLI::Range(0.0, ispars::recipe_override("stretch_slack").max));
  command.add_option("--stretch-slack-after", after,
                     "Stretch rules: the slack applies from this sample on (default 0: from the first)")
      ->check(CLI::Range(0.0, ispars::recipe_override("stretch_slack_after").max));
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ispars::lab;
  spdlog::set_level(spdlog::level::warn);

  // Method and rule-set names as build_recipe.hpp declares them (the one list of each).
  const CLI::Validator spars_variant(
      [](std::string& text) {
        return ispars::parse_spars_variant(text)
                   ? std::string()
                   : "unknown variant '" + text + "' (" + ispars::spars_variant_names() + ")";
      },
      "stretch|alg1");
  const CLI::Validator build_method(
      [](std::string& text) {
        return ispars::parse_build_method(text)
                   ? std::string()
                   : "unknown method '" + text + "' (" + ispars::build_method_names() + ")";
      },
      "dense|spars|ispars|irisc|ispars2");

  CLI::App app{"ispars-lab: scene reports, geometry benchmarks and roadmap experiments"};
  app.require_subcommand(1);

  auto* scene = app.add_subcommand("scene", "Scene files")->require_subcommand(1);
  SceneInfoOptions info;
  auto* info_cmd = scene->add_subcommand(
      "info", "Triangles, bounds, POIs, root clearance and POIs seen from random valid configurations");
  info_cmd->add_option("scene", info.scene, "Scene YAML file")->required();
  info_cmd->add_flag("--json", info.json, "Print one JSON object as the last line of stdout");
  info_cmd->add_option("--samples", info.samples, "Random valid configurations for the coverage estimate")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}));
  info_cmd->add_option("--seed", info.seed, "Seed of the random configurations");

  auto* bench = app.add_subcommand("bench", "Benchmarks that print figures (JSON with --json)")
                    ->require_subcommand(1);
  BenchGeometryOptions geometry;
  auto* geometry_cmd = bench->add_subcommand(
      "geometry", "Point, segment and visibility query costs against brute-force and FCL references");
  geometry_cmd->add_option("scene", geometry.scene, "Scene YAML file")->required();
  geometry_cmd->add_flag("--json", geometry.json, "Print one JSON object as the last line of stdout");
  geometry_cmd->add_option("--queries", geometry.queries, "Queries per fast-path measurement")
      ->check(CLI::Range(std::size_t{64}, std::size_t{10'000'000}));
  geometry_cmd->add_option("--reference-queries", geometry.reference_queries,
                           "Queries through the brute-force reference")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000}));
  geometry_cmd->add_option("--seed", geometry.seed, "Seed of the random queries");

  BenchBuildOptions bench_build;
  auto* bench_build_cmd = bench->add_subcommand("build", "Construction time, checks per sample and peak memory against N");
  bench_build_cmd->add_option("scene", bench_build.scene, "Scene YAML file")->required();
  bench_build_cmd->add_option("--method", bench_build.method, "dense | spars | ispars | irisc | ispars2")
      ->check(build_method);
  bench_build_cmd->add_option("--variant", bench_build.variant, "spars, ispars: stretch (default) or alg1")
      ->check(spars_variant);
  bench_build_cmd->add_option("--samples", bench_build.samples, "N")->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}));
  add_stretch_slack_options(*bench_build_cmd, bench_build.stretch_slack, bench_build.stretch_slack_after);
  bench_build_cmd->add_option("--checkpoints", bench_build.checkpoints, "Report rows")->check(CLI::Range(std::size_t{1}, std::size_t{1000}));
  bench_build_cmd->add_option("--seed", bench_build.seed, "Seed");
  bench_build_cmd->add_option("--threads", bench_build.threads, "Threads")->check(CLI::Range(1u, 64u));
  bench_build_cmd->add_flag("--json", bench_build.json, "Print one JSON object as the last line of stdout");

  BenchTourOptions bench_tour;
  auto* bench_tour_cmd = bench->add_subcommand(
      "tour", "The tour solver on a large roadmap: first tour, budget, memory, stop latency");
  bench_tour_cmd->add_option("scene", bench_tour.scene, "Scene YAML file")->required();
  bench_tour_cmd->add_option("--method", bench_tour.method, "dense | spars | ispars | irisc | ispars2")
      ->check(build_method);
  bench_tour_cmd->add_option("--samples", bench_tour.samples, "N")->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}));
  bench_tour_cmd->add_option("--seed", bench_tour.seed, "Seed of the roadmap and the search");
  bench_tour_cmd->add_option("--budget", bench_tour.budget, "Seconds of search")->check(CLI::Range(0.01, 3600.0));
  bench_tour_cmd->add_option("--stop-at", bench_tour.stop_at, "Request a stop this many seconds after the start")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 3600.0));
  bench_tour_cmd->add_flag("--json", bench_tour.json, "Print one JSON object as the last line of stdout");

  BuildCommandOptions build;
  auto* build_cmd = app.add_subcommand("build", "Build a roadmap: dense, spars, ispars, irisc or ispars2");
  build_cmd->add_option("scene", build.scene, "Scene YAML file")->required();
  build_cmd->add_option("--method", build.method, "dense | spars | ispars | irisc | ispars2")
      ->required()
      ->check(build_method);
  build_cmd->add_option("--samples", build.samples, "Samples to draw (N)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{100'000'000}));
  build_cmd->add_option("--seed", build.seed, "Seed of the sample stream");
  build_cmd->add_option("--variant", build.variant,
                        "spars, ispars: stretch (default: bounds routes between nearby sparse vertices) or alg1 "
                        "(the paper's Alg. 1 read literally)")
      ->check(spars_variant);
  build_cmd->add_option("--threads", build.threads, "Threads for per-sample checks (same roadmap for any count)")
      ->check(CLI::Range(1u, 64u));
  build_cmd->add_option("--p-accept", build.p_accept, "IRIS-C: admission probability without new coverage")
      ->check(CLI::Range(0.0, 1.0));
  build_cmd->add_option("--stretch-slack", build.stretch_slack,
                        "Stretch rules: additive slack of the bounds, a fraction of Delta (default 0)")
      ->check(CLI::Range(0.0, ispars::recipe_override("stretch_slack").max));
  build_cmd->add_option("--stretch-slack-after", build.stretch_slack_after,
                        "Stretch rules: the slack applies from this sample on (default 0: from the first)")
      ->check(CLI::Range(0.0, ispars::recipe_override("stretch_slack_after").max));
  build_cmd->add_flag("--verify", build.verify, "Check validity, costs and the inspection invariant exactly");
  build_cmd->add_option("--fresh", build.fresh, "Also check Invariant 1 on this many fresh samples (a seed of its own)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{10'000'000}));
  build_cmd->add_option("--out", build.out, "Write the roadmap (and its dense pair) as JSON");
  build_cmd->add_option("--iris", build.iris, "Write IRIS text files PREFIX_vertex, PREFIX_edge, PREFIX_conf");
  build_cmd->add_flag("--json", build.json, "Print one JSON object as the last line of stdout");

  auto* experiment = app.add_subcommand("experiment", "Reproduce the paper's experiments")->require_subcommand(1);
  ExperimentOptions exp;
  const auto common = [&](CLI::App* cmd) {
    cmd->add_option("--scenes", exp.scenes_dir, "Directory of the scene YAML files");
    cmd->add_option("--threads", exp.threads, "Threads per build")->check(CLI::Range(1u, 64u));
    cmd->add_flag("--json", exp.json, "Print one JSON object as the last line of stdout");
  };
  auto* table_cmd = experiment->add_subcommand("table", "Table II: |V|, |E|, coverage over seeds, three scenes");
  common(table_cmd);
  table_cmd->add_option("--seeds", exp.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  auto* scaling_cmd = experiment->add_subcommand("scaling", "Fig. 5: |V|, |E|, coverage, checks against N");
  common(scaling_cmd);
  scaling_cmd->add_option("--scene", exp.scene, "Scene name in --scenes");
  scaling_cmd->add_option("--seeds", exp.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  scaling_cmd->add_option("--max-samples", exp.max_samples, "Largest N")->check(CLI::Range(250, 100'000'000));
  scaling_cmd->add_option("--pois", exp.pois, "K")->check(CLI::Range(1, 10'000'000));
  scaling_cmd->add_option("--delta", exp.delta, "delta (0: calibrate to the paper's density)")->check(CLI::Range(0.0, 1e6));
  scaling_cmd->add_option("--csv", exp.csv, "Write per-seed rows here (and means to FILE.summary)");
  scaling_cmd->add_option("--png", exp.png, "Write the plot here (gnuplot)");
  auto* spanner_cmd = experiment->add_subcommand(
      "spanner", "Route quality: sparse viewpoint pairs against dense routes and segments, by distance, per variant");
  common(spanner_cmd);
  spanner_cmd->add_option("--scene", exp.scene, "Scene name in --scenes");
  spanner_cmd->add_flag("--calibrate", exp.calibrate,
                        "The paper's N, K and calibrated delta for the scene (water_tower, truss_bridge, caric_city)");
  spanner_cmd->add_option("--samples", exp.samples, "N")->check(CLI::Range(1, 100'000'000));
  spanner_cmd->add_option("--pairs", exp.pairs, "Random pairs of dense vertices (SPARS's bound)")
      ->check(CLI::Range(1, 10'000'000));
  spanner_cmd->add_option("--pois", exp.pois, "K")->check(CLI::Range(1, 10'000'000));
  spanner_cmd->add_option("--delta", exp.delta, "delta (0: the scene's, or calibrated)")->check(CLI::Range(0.0, 1e6));
  spanner_cmd->add_option("--seed", exp.build_seed, "Seed of the build (and of the POIs)");
  spanner_cmd->add_option("--pairs-seed", exp.seeds, "Seed of the random dense pairs");
  spanner_cmd->add_option("--max-sources", exp.max_sources, "Measure pairs from at most this many viewpoints (0: all)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{100'000'000}));
  spanner_cmd->add_option("--variants", exp.variants,
                          "Rule sets to compare: " + ispars::spars_variant_names() +
                              ", spars (SPARS: alg1 without the inspection test), or a rule set as "
                              "--rule-sets of ablation reads it (e.g. stretch+shortcut)")
      ->delimiter(',');
  auto* anytime_cmd = experiment->add_subcommand(
      "anytime", "Fig. 4: best tour against solver time on Dense, Inspection-SPARS and IRIS-C roadmaps");
  common(anytime_cmd);
  anytime_cmd->add_option("--seeds", exp.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  anytime_cmd->add_option("--iterations", exp.iterations,
                          "Solver iterations per roadmap: the same work for each (0: a time budget instead)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}));
  anytime_cmd->add_option("--budget", exp.budget, "With --iterations 0: solver seconds per roadmap (the paper: 150)")
      ->check(CLI::Range(0.1, 1e5));
  anytime_cmd->add_option("--cap", exp.cap, "With --iterations: wall-clock cap per tour, seconds")
      ->check(CLI::Range(0.1, 1e5));
  anytime_cmd->add_option("--jobs", exp.jobs, "Roadmaps solved at once (one solver thread each)")->check(CLI::Range(1u, 64u));
  anytime_cmd->add_option("--csv", exp.csv, "CSV of mean +- sd of the best tour against time");
  anytime_cmd->add_option("--png", exp.png, "Plot (gnuplot)");
  anytime_cmd->add_flag("--replot", exp.replot, "Only draw --png from the --csv of an earlier run");
  anytime_cmd->add_option("--bound-seconds", exp.bound_seconds, "Seconds of LP lower bound per roadmap (0: none)")
      ->check(CLI::Range(0.0, 1e5));

  auto* ablation_cmd = experiment->add_subcommand(
      "ablation", "Sparse-roadmap rules one by one: size, route stretch, Invariant 1 and tours (same targets, same work)");
  common(ablation_cmd);
  ablation_cmd->add_option("--scene", exp.scene, "water_tower, truss_bridge or caric_city (the paper's setting)");
  ablation_cmd->add_option("--seeds", exp.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  ablation_cmd->add_option("--delta", exp.delta, "delta (0: calibrated)")->check(CLI::Range(0.0, 1e6));
  ablation_cmd->add_option("--samples", exp.samples, "N (0: the paper's)")->check(CLI::Range(0, 100'000'000));
  ablation_cmd->add_option("--rule-sets", exp.rule_sets,
                           "Rule sets: alg1 or stretch, then +R / -R with R in join, witness, shortcut")
      ->delimiter(',');
  ablation_cmd->add_option("--iterations", exp.iterations, "Solver iterations per roadmap")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  ablation_cmd->add_option("--cap", exp.cap, "Wall-clock cap per tour, seconds")->check(CLI::Range(0.1, 1e5));
  add_stretch_slack_options(*ablation_cmd, exp.stretch_slack, exp.stretch_slack_after);
  ablation_cmd->add_option("--jobs", exp.jobs, "Tours solved at once (one solver thread each)")->check(CLI::Range(1u, 64u));

  TourCommandOptions tour;
  auto* tour_cmd = app.add_subcommand("tour", "An inspection tour (GIP) on a roadmap file or IRIS files");
  tour_cmd->add_option("roadmap", tour.roadmap, "Roadmap JSON (ispars-lab build --out, ispars snapshot --out)");
  tour_cmd->add_option("--graph", tour.graph, "Which graph of the file")->check(CLI::IsMember({"roadmap", "dense"}));
  tour_cmd->add_option("--iris", tour.iris, "IRIS files PREFIX_vertex and PREFIX_edge instead of a roadmap file");
  tour_cmd->add_flag("--all-edges", tour.all_edges, "IRIS: keep edges marked invalid (as the published solver read them)");
  tour_cmd->add_option("--budget", tour.budget, "Seconds of search")->required()->check(CLI::Range(0.0, 1e6));
  tour_cmd->add_option("--seed", tour.seed, "Seed");
  tour_cmd->add_option("--threads", tour.threads, "Search threads (one chain each)")->check(CLI::Range(1u, 64u));
  tour_cmd->add_option("--iterations", tour.iterations, "Stop after this many search iterations per thread (deterministic)");
  tour_cmd->add_option("--targets", tour.targets, "A file of target POI ids (default: all seen from the root)");
  tour_cmd->add_option("--bound", tour.bound, "lp: prove a lower bound by linear programming beside the search; simple")
      ->check(CLI::IsMember({"lp", "simple"}));
  tour_cmd->add_flag("--json", tour.json, "Print one JSON object as the last line of stdout");
  tour_cmd->add_option("--out", tour.out, "Write the tour (walk, positions, trace, path: what render draws) as JSON");
  tour_cmd->add_option("--scene", tour.scene, "The roadmap's scene YAML: also shortcut the tour (straight checked segments)")
      ->check(CLI::ExistingFile);

  RenderCommandOptions render;
  auto* render_cmd = app.add_subcommand("render", "A PNG of a scene, a roadmap file's graphs, its POIs and a tour");
  render_cmd->add_option("scene", render.scene, "Scene YAML")->required()->check(CLI::ExistingFile);
  render_cmd->add_option("--roadmap", render.roadmap, "Roadmap JSON (ispars-lab build --out, ispars snapshot --out)");
  render_cmd->add_flag("--dense", render.dense, "Also draw the file's dense graph, faint");
  render_cmd->add_option("--tour", render.tour, "Tour JSON (ispars-lab tour --out)");
  render_cmd->add_option("--out", render.out, "The PNG file to write")->required();
  render_cmd->add_option("--width", render.width, "Pixels")->check(CLI::Range(16, 8192));
  render_cmd->add_option("--height", render.height, "Pixels")->check(CLI::Range(16, 8192));
  render_cmd->add_option("--eye", render.eye, "Camera position X Y Z (default: framed from the front-right)")->expected(3);
  render_cmd->add_option("--target", render.target, "Camera target X Y Z (with --eye)")->expected(3);
  render_cmd->add_option("--fov", render.fov, "Vertical field of view, degrees")->check(CLI::Range(1.0, 170.0));
  render_cmd->add_option("--max-edges", render.max_edges, "Edges of each graph drawn at most (an evenly spread subset)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}));
  render_cmd->add_flag("--json", render.json, "Print one JSON object as the last line of stdout");

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
    if (info_cmd->parsed()) return run_scene_info(info);
    if (geometry_cmd->parsed()) return run_bench_geometry(geometry);
    if (build_cmd->parsed()) return run_build(build);
    if (tour_cmd->parsed()) return run_tour(tour);
    if (render_cmd->parsed()) return run_render(render);
    if (bench_build_cmd->parsed()) return run_bench_build(bench_build);
    if (bench_tour_cmd->parsed()) return run_bench_tour(bench_tour);
    if (table_cmd->parsed()) return run_experiment_table(exp);
    if (scaling_cmd->parsed()) {
      if (exp.seeds == 6) exp.seeds = 10;  // the paper's Fig. 5 uses ten seeds
      if (exp.pois == 0) exp.pois = 100;   // the paper's K on the water tower
      return run_experiment_scaling(exp);
    }
    if (anytime_cmd->parsed()) return run_experiment_anytime(exp);
    if (ablation_cmd->parsed()) return run_experiment_ablation(exp);
    if (spanner_cmd->parsed()) {
      if (exp.seeds == 6) exp.seeds = 1;
      return run_experiment_spanner(exp);
    }
  } catch (const ispars::InputError& e) {
    std::cerr << "ispars-lab: error: " << e.what() << '\n';
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ispars-lab: internal error: " << e.what() << '\n';
    return 1;
  }
  return 1;
}
