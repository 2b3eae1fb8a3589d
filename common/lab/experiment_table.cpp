// `ispars-lab experiment table`: the paper's Table II (|V|, |E|, covered POIs; mean +- sd over
// seeds) for Dense, SPARS, Inspection-SPARS (both rule sets) and IRIS-C, at physical scale and calibrated;
// and Dense-wide, Dense joined within 2 Delta (a sparse edge's reach), the fair baseline for tours.

#include <fmt/format.h>

#include <map>

#include <iostream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "json_output.hpp"
#include "timing.hpp"

namespace ispars::lab {
namespace {

struct PaperRow {
  const char* method;
  const char* vertices;
  const char* edges;
  const char* covered;
};

struct TableScene {
  const char* name;
  std::size_t samples;
  std::size_t pois;
  double paper_degree;  // 2|E|/|V| of the paper's Dense roadmap
  std::vector<PaperRow> paper;
};

const std::vector<TableScene>& table_scenes() {
  static const std::vector<TableScene> scenes{
      {"water_tower",
       4000,
       100,
       2.0 * 14474 / 3933,
       {{"dense", "3933 +- 17", "14474 +- 198", "73.8 +- 4.1"},
        {"ispars", "476 +- 10", "2086 +- 14", "76.2 +- 3.6"},
        {"irisc", "843 +- 24", "3168 +- 165", "70.8 +- 3.2"}}},
      {"truss_bridge",
       5000,
       500,
       2.0 * 27508 / 4955,
       {{"dense", "4955 +- 11", "27508 +- 457", "404.2 +- 6.1"},
        {"ispars", "875 +- 18", "3589 +- 42", "404.8 +- 6.1"},
        {"irisc", "1199 +- 28", "3935 +- 103", "381.7 +- 23.0"}}},
      {"caric_city",
       7000,
       500,
       2.0 * 16891 / 6391,
       {{"dense", "6391 +- 40", "16891 +- 281", "225.5 +- 11.6"},
        {"ispars", "1425 +- 29", "3165 +- 61", "249.8 +- 8.7"},
        {"irisc", "1462 +- 48", "3101 +- 224", "192.7 +- 5.0"}}},
  };
  return scenes;
}

}  // namespace

int run_experiment_table(const ExperimentOptions& options) {
  // Each method, and SPARS and Inspection-SPARS under both rule sets (-alg1: Alg. 1 read literally).
  struct TableMethod {
    std::string name;
    BuildMethod method;
    SparsVariant variant;
    bool wide = false;  // joined within 2 Delta = 3 delta
  };
  const std::vector<TableMethod> methods{{"dense", BuildMethod::dense, SparsVariant::stretch},
                                         {"spars", BuildMethod::spars, SparsVariant::stretch},
                                         {"spars-alg1", BuildMethod::spars, SparsVariant::alg1},
                                         {"ispars", BuildMethod::ispars, SparsVariant::stretch},
                                         {"ispars-alg1", BuildMethod::ispars, SparsVariant::alg1},
                                         {"irisc", BuildMethod::irisc, SparsVariant::stretch},
                                         {"dense-wide", BuildMethod::dense, SparsVariant::stretch, true}};
  nlohmann::json results = nlohmann::json::array();
  std::cout << fmt::format("# Table II, reproduced ({} seeds; command: ispars-lab experiment table --seeds {})\n\n",
                           options.seeds, options.seeds);
  for (const TableScene& ts : table_scenes()) {
    const scene_files::SceneConfig base = scene_files::parse_scene_config(options.scenes_dir + "/" + ts.name + ".yaml");
    const double calibrated = calibrate_delta(base, ts.samples, ts.paper_degree, options.threads);
    std::cout << fmt::format("## {} (N = {}, K = {})\n\n", ts.name, ts.samples, ts.pois);
    std::cout << fmt::format(
        "Parameter sets: physical delta = {:.3f}, Delta = {:.3f} (deploy/scenes); calibrated delta = {:.3f}, "
        "Delta = {:.3f} (dense mean degree {:.2f} at N = {}, seed 1, as in the paper). t = {}.\n\n",
        base.dense_delta, base.sparse_delta, calibrated, 1.5 * calibrated, ts.paper_degree, ts.samples, base.stretch);
    std::cout << "| parameters | method | \\|V\\| | \\|E\\| | covered POIs (root component) | covered POIs (all) "
                 "| invariant violations | seconds |\n|---|---|---|---|---|---|---|---|\n";
    for (const auto& [label, delta] : {std::pair<const char*, double>{"physical", base.dense_delta},
                                       std::pair<const char*, double>{"calibrated", calibrated}}) {
      std::map<std::string, std::vector<RunFigures>> runs;
      std::map<std::string, std::vector<double>> violations;
      for (std::uint64_t seed = 1; seed <= options.seeds; ++seed) {
        const planning::Scene narrow = planning::Scene::build(scene_variant(base, ts.pois, seed, delta));
        const planning::Scene wide = planning::Scene::build(scene_variant(base, ts.pois, seed, 3.0 * delta));
        for (const TableMethod& m : methods) {
          const planning::Scene& scene = m.wide ? wide : narrow;
          planning::BuildOptions build;
          build.seed = seed;
          build.threads = options.threads;
          build.variant = m.variant;
          const planning::CheckCounts before = scene.counts();
          const double t0 = now_seconds();
          const auto builder = planning::make_roadmap_builder(m.method, scene, build);
          builder->extend(ts.samples);
          runs[m.name].push_back(figures_of(*builder, scene.counts() - before, now_seconds() - t0));
          if (builder->dense() != nullptr) {
            violations[m.name].push_back(static_cast<double>(
                planning::verify_sparse_pair(scene, builder->roadmap(), *builder->dense(), builder->dense_ids())
                    .invariant_violations));
          }
        }
      }
      for (const TableMethod& tm : methods) {
        const std::string& m = tm.name;
        std::vector<double> v, e, root, all, secs;
        for (const RunFigures& f : runs[m]) {
          v.push_back(static_cast<double>(f.vertices));
          e.push_back(static_cast<double>(f.edges));
          root.push_back(static_cast<double>(f.covered_root));
          all.push_back(static_cast<double>(f.covered));
          secs.push_back(f.seconds);
        }
        const std::string viol = violations.count(m) ? mean_sd_cell(violations[m], 1) : "-";
        std::cout << fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.2f} |\n", label, m, mean_sd_cell(v, 0),
                                 mean_sd_cell(e, 0), mean_sd_cell(root, 1), mean_sd_cell(all, 1), viol,
                                 mean_sd(secs).mean);
        results.push_back(
            {{"scene", ts.name},
             {"parameters", label},
             {"delta", delta},
             {"method", m},
             {"samples", ts.samples},
             {"pois", ts.pois},
             {"vertices", v},
             {"edges", e},
             {"covered_root", root},
             {"covered", all},
             {"invariant_violations", violations.count(m) ? nlohmann::json(violations[m]) : nlohmann::json()},
             {"seconds", secs}});
      }
    }
    for (const PaperRow& row : ts.paper) {
      std::cout << fmt::format("| paper | {} | {} | {} | {} | - | - | - |\n", row.method, row.vertices, row.edges,
                               row.covered);
    }
    std::cout << '\n';
  }
  if (options.json) std::cout << nlohmann::json{{"table", results}}.dump() << std::endl;
  return 0;
}

CLI::App* add_experiment_table_command(CLI::App& parent, ExperimentOptions& options) {
  auto* cmd = parent.add_subcommand("table", "Table II: |V|, |E|, coverage over seeds, three scenes");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--seeds", options.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  return cmd;
}

}  // namespace ispars::lab
