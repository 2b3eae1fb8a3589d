// `ispars-lab bench build`: construction speed and memory as N grows: time, checks and
// microseconds per sample in each interval between checkpoints, and the peak resident memory.

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <string>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "json_output.hpp"
#include "lab_build.hpp"
#include "timing.hpp"

namespace ispars::lab {

int run_bench_build(const BenchBuildOptions& options) {
  const planning::Scene base = planning::Scene::load(options.scene);
  const LabBuild lab =
      make_lab_build(base, options.method, options.variant, options.request, options.threads, "ispars-lab bench build");
  const planning::Scene& scene = *lab.scene;
  const auto& builder = lab.builder;
  const BuildMethod method = lab.recipe.method;
  const RoadmapRecipe& r = lab.recipe;
  const std::size_t samples = options.request.samples;
  const planning::CheckCounts start = scene.counts();
  const double t0 = now_seconds();
  nlohmann::json rows = nlohmann::json::array();
  std::cout << fmt::format("{} ({} rules, stretch slack {} Delta from sample {}) on {}, seed {}, {} thread(s)\n",
                           options.method, to_string(r.variant), r.stretch_slack, r.stretch_slack_after,
                           scene.config().name, r.seed, options.threads);
  std::cout << fmt::format("{:>9} {:>9} {:>9} {:>9} {:>9} {:>12} {:>12} {:>10}\n", "N", "seconds", "us/sample",
                           "seg/sample", "|V|", "|E|", "dense |E|", "peak MiB");
  std::size_t previous = 0;
  double previous_t = 0.0;
  planning::CheckCounts previous_checks;
  for (std::size_t k = 1; k <= options.checkpoints; ++k) {
    const std::size_t target = samples * k / options.checkpoints;
    builder->extend(target - previous);
    const double elapsed = now_seconds() - t0;
    const planning::CheckCounts checks = scene.counts() - start;
    const double interval = static_cast<double>(target - previous);
    const double us_per_sample = interval > 0 ? 1e6 * (elapsed - previous_t) / interval : 0.0;
    const double segments_per_sample =
        interval > 0 ? static_cast<double>(checks.segment - previous_checks.segment) / interval : 0.0;
    const Roadmap& g = builder->roadmap();
    const std::size_t dense_edges =  // 0: no dense graph (irisc, ispars2)
        builder->dense()               ? builder->dense()->edge_count()
        : method == BuildMethod::dense ? g.edge_count()
                                       : 0;
    const double rss = peak_rss_mib();
    rows.push_back({{"samples", target},
                    {"seconds", elapsed},
                    {"us_per_sample", us_per_sample},
                    {"segment_checks_per_sample", segments_per_sample},
                    {"vertices", g.vertex_count()},
                    {"edges", g.edge_count()},
                    {"dense_edges", dense_edges},
                    {"peak_rss_mib", rss},
                    {"checks", to_json(checks)}});
    std::cout << fmt::format("{:>9} {:>9.2f} {:>9.1f} {:>9.1f} {:>9} {:>12} {:>12} {:>10.0f}\n", target, elapsed,
                             us_per_sample, segments_per_sample, g.vertex_count(), g.edge_count(), dense_edges, rss)
              << std::flush;
    previous = target;
    previous_t = elapsed;
    previous_checks = checks;
  }
  const double seconds = now_seconds() - t0;
  if (options.json) {
    std::cout << nlohmann::json{{"scene", scene.config().name},
                                {"method", options.method},
                                {"variant", std::string(to_string(r.variant))},
                                {"stretch_slack", r.stretch_slack},
                                {"stretch_slack_after", r.stretch_slack_after},
                                {"samples", samples},
                                {"seed", r.seed},
                                {"threads", options.threads},
                                {"seconds", seconds},
                                {"samples_per_second", static_cast<double>(samples) / seconds},
                                {"peak_rss_mib", peak_rss_mib()},
                                {"checkpoints", rows}}
                     .dump()
              << std::endl;
  }
  return 0;
}

CLI::App* add_bench_build_command(CLI::App& parent, BenchBuildOptions& options) {
  auto* cmd = parent.add_subcommand("build", "Construction time, checks per sample and peak memory against N");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  add_request_flags(*cmd, options.method, options.variant, options.request);
  cmd->add_option("--checkpoints", options.checkpoints, "Report rows")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000}));
  cmd->add_option("--threads", options.threads, "Threads")->check(CLI::Range(1u, 64u));
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  return cmd;
}

}  // namespace ispars::lab
