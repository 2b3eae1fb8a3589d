// `ispars-lab experiment scaling`: the paper's Fig. 5: |V|, |E|, coverage and collision checks
// against N, for every method, over seeds; a CSV and a PNG plot (gnuplot).

#include <fmt/format.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "timing.hpp"

namespace ispars::lab {
namespace {

std::vector<std::size_t> checkpoints(std::size_t max_samples) {
  std::vector<std::size_t> out;
  for (std::size_t n = 250; n < max_samples; n *= 2) out.push_back(n);
  out.push_back(max_samples);
  return out;
}

void write_plot(const std::string& data, const std::string& png, const std::string& title) {
  std::ostringstream script;
  script << "set terminal pngcairo size 1400,1000 font 'Sans,11'\n"
         << "set termoption noenhanced\n"
         << "set output '" << png << "'\n"
         << "set multiplot layout 2,2 title '" << title << "'\n"
         << "set logscale x\nset key left top\nset grid\nset xlabel 'samples N'\n";
  const auto panel = [&](const char* ylabel, int column, bool log_y) {
    script << (log_y ? "set logscale y\n" : "unset logscale y\n") << "set ylabel '" << ylabel << "'\n"
           << "plot for [i=0:3] '" << data << "' index i using 1:" << column << ":" << column + 1
           << " with yerrorlines title columnheader(1)\n";
  };
  panel("vertices |V|", 2, true);
  panel("edges |E|", 4, true);
  panel("POIs covered (root component)", 6, false);
  panel("collision checks (point + segment)", 8, true);
  script << "unset multiplot\n";
  run_gnuplot(png, script.str());
}

}  // namespace

int run_experiment_scaling(const ExperimentOptions& options) {
  const std::vector<BuildMethod> methods{BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars,
                                         BuildMethod::irisc};
  const scene_files::SceneConfig base =
      scene_files::parse_scene_config(options.scenes_dir + "/" + options.scene + ".yaml");
  // Calibrated as in the paper's density: the water tower's Dense mean degree 7.36 at N = 4000.
  const double delta =
      options.delta > 0.0 ? options.delta : calibrate_delta(base, 4000, 2.0 * 14474 / 3933, options.threads);
  const std::vector<std::size_t> marks = checkpoints(options.max_samples);

  std::string csv =
      "method,seed,samples,vertices,edges,pois_covered,pois_covered_root,point_checks,segment_checks,rays,seconds\n";
  // (method, N) -> per-seed values of each column
  std::map<std::pair<int, std::size_t>, std::vector<std::array<double, 5>>> table;
  for (std::uint64_t seed = 1; seed <= options.seeds; ++seed) {
    const planning::Scene scene = planning::Scene::build(scene_variant(base, options.pois, seed, delta));
    for (const BuildMethod m : methods) {
      planning::BuildOptions build;
      build.seed = seed;
      build.threads = options.threads;
      const planning::CheckCounts start = scene.counts();
      const double t0 = now_seconds();
      const auto builder = planning::make_roadmap_builder(m, scene, build);
      for (const std::size_t n : marks) {
        builder->extend(n - builder->samples());
        const RunFigures f = figures_of(*builder, scene.counts() - start, now_seconds() - t0);
        csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{:.4f}\n", to_string(m), seed, n, f.vertices, f.edges,
                           f.covered, f.covered_root, f.checks.point, f.checks.segment, f.checks.rays, f.seconds);
        table[{static_cast<int>(m), n}].push_back({static_cast<double>(f.vertices), static_cast<double>(f.edges),
                                                   static_cast<double>(f.covered_root),
                                                   static_cast<double>(f.checks.point + f.checks.segment), f.seconds});
      }
    }
  }

  // Per method, one gnuplot block: N, then mean and sd of |V|, |E|, coverage, checks, seconds.
  std::string summary;
  nlohmann::json json = nlohmann::json::array();
  for (const BuildMethod m : methods) {
    summary += fmt::format("{}\n", to_string(m));
    for (const std::size_t n : marks) {
      const auto& rows = table[{static_cast<int>(m), n}];
      summary += fmt::format("{}", n);
      nlohmann::json point = {{"method", to_string(m)}, {"samples", n}};
      const char* names[] = {"vertices", "edges", "pois_covered_root", "collision_checks", "seconds"};
      for (std::size_t c = 0; c < 5; ++c) {
        std::vector<double> values;
        for (const auto& r : rows) values.push_back(r[c]);
        const MeanSd ms = mean_sd(values);
        summary += fmt::format(" {:.3f} {:.3f}", ms.mean, ms.sd);
        point[names[c]] = {{"mean", ms.mean}, {"sd", ms.sd}};
      }
      summary += '\n';
      json.push_back(point);
    }
    summary += "\n\n";
  }

  if (!options.csv.empty()) {
    std::ofstream out(options.csv);
    if (!out) throw params::InputError(options.csv, "--csv", "cannot open for writing");
    out << csv;
    std::ofstream(options.csv + ".summary")
        << "# method blocks: N, mean sd of |V|, |E|, POIs covered (root), checks, seconds\n"
        << summary;
  }
  if (!options.png.empty()) {
    const std::string data = options.png + ".dat";
    std::ofstream(data) << summary;
    write_plot(data, options.png,
               fmt::format("{}: delta {:.3f}, Delta {:.3f}, K = {}, {} seeds (mean +- sd)", options.scene, delta,
                           1.5 * delta, options.pois, options.seeds));
    std::remove(data.c_str());
  }
  std::cout << fmt::format("scaling on {}: delta {:.3f}, Delta {:.3f}, K = {}, {} seeds, N up to {}\n", options.scene,
                           delta, 1.5 * delta, options.pois, options.seeds, options.max_samples);
  std::cout << "method N |V| |E| POIs(root) checks seconds (means)\n";
  for (const auto& p : json) {
    std::cout << fmt::format("{:<7}{:>7}{:>10.0f}{:>10.0f}{:>8.1f}{:>12.0f}{:>9.3f}\n", p["method"].get<std::string>(),
                             p["samples"].get<std::size_t>(), p["vertices"]["mean"].get<double>(),
                             p["edges"]["mean"].get<double>(), p["pois_covered_root"]["mean"].get<double>(),
                             p["collision_checks"]["mean"].get<double>(), p["seconds"]["mean"].get<double>());
  }
  if (options.json) std::cout << nlohmann::json{{"delta", delta}, {"scaling", json}}.dump() << std::endl;
  return 0;
}

CLI::App* add_experiment_scaling_command(CLI::App& parent, ExperimentOptions& options) {
  options.seeds = 10;  // the paper's Fig. 5 uses ten seeds
  options.pois = 100;  // the paper's K on the water tower
  auto* cmd = parent.add_subcommand("scaling", "Fig. 5: |V|, |E|, coverage, checks against N");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--scene", options.scene, "Scene name in --scenes");
  cmd->add_option("--seeds", options.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  cmd->add_option("--max-samples", options.max_samples, "Largest N")->check(CLI::Range(250, 100'000'000));
  cmd->add_option("--pois", options.pois, "K")->check(CLI::Range(1, 10'000'000));
  cmd->add_option("--delta", options.delta, "delta (0: calibrate to the paper's density)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--csv", options.csv, "Write per-seed rows here (and means to FILE.summary)");
  cmd->add_option("--png", options.png, "Write the plot here (gnuplot)");
  return cmd;
}

}  // namespace ispars::lab
