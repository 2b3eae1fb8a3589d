// `ispars-lab experiment ablation`: which sparse-roadmap rule does what. For one scene in the
// paper's calibrated setting, each rule set (alg1, stretch, and single rules on and off) is built
// on the same samples; reported: |V|, |E|, components, route stretch between sparse viewpoints,
// Invariant 1, and tours with the same targets and the same solver work, against Dense, IRIS-C and
// (with --wide) Dense-wide (Dense joined within 2 Delta): each tour as searched (the roadmap walk) and as flown
// (the walk shortcut in the scene, checked independently: tour_shortcut.hpp, flown_tour_check.hpp).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <iostream>
#include <map>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/planning/builders/dense_builder.hpp"
#include "ispars/planning/builders/irisc_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/tour/flown_tour_check.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "tour_support.hpp"

namespace ispars::lab {
namespace {

struct Row {
  std::vector<double> vertices, edges, components, violations, tour, tour_ratio;
  std::vector<double> flown, flown_ratio, flown_wide_ratio;  // shortcut tours: length, / Dense's, / Dense-wide's
  std::vector<double> median3, p95_3, over3;                 // within 3 Delta, against dense routes
  std::vector<double> median_bin[4];                         // per bin, against dense routes
  std::vector<double> segment_median3, segment_p95_3;        // within 3 Delta, against segments
};

std::string mean_cell(const std::vector<double>& v, int decimals) {
  return v.empty() ? "-" : fmt::format("{:.{}f}", mean_sd(v).mean, decimals);
}

// The flown length of each tour: its walk shortcut in `scene` (deterministic), checked by
// re-deriving what each stop sees; a tour that fails the check stops the experiment.
std::vector<double> flown_costs(const planning::Scene& scene, std::span<const InspectionGraph* const> graphs,
                                const std::vector<std::vector<Vec3>>& positions, std::span<const PoiId> targets,
                                const std::vector<planning::GipResult>& tours, const std::vector<std::string>& names) {
  const planning::SegmentValid valid = [&scene](const Vec3& a, const Vec3& b) { return scene.segment_valid(a, b); };
  std::vector<double> costs;
  for (std::size_t i = 0; i < tours.size(); ++i) {
    const planning::ShortcutTour sc = planning::shortcut_tour(*graphs[i], positions[i], targets, tours[i].tour, valid);
    const planning::FlownTourCheck check =
        planning::check_flown_tour(scene, positions[i][0], targets, sc.path, sc.cost);
    if (!check.valid()) {
      throw std::runtime_error(fmt::format("{}: the flown tour failed its check: {}", names[i], check.problem));
    }
    costs.push_back(sc.cost);
  }
  return costs;
}

}  // namespace

int run_experiment_ablation(const ExperimentOptions& options) {
  const PaperSetting& paper = paper_setting(options.scene);
  const std::size_t samples = options.samples > 0 ? options.samples : paper.samples;
  const scene_files::SceneConfig base =
      scene_files::parse_scene_config(options.scenes_dir + "/" + options.scene + ".yaml");
  const double delta =
      options.delta > 0.0 ? options.delta : calibrate_delta(base, samples, paper.degree, options.threads);
  std::vector<planning::SparsRules> rule_sets;
  for (const std::string& name : options.rule_sets) rule_sets.push_back(parse_rule_set(name, "--rule-sets"));
  const SolverWork work{options.iterations, options.cap, options.jobs};
  std::cout << fmt::format(
      "# Ablation on {} (calibrated: delta {:.3f}, Delta {:.3f}; N = {}, K = {}; {} seeds); tours: the same targets "
      "I_t for every roadmap of a seed, {} solver iterations each (one thread, {} at a time, {:.0f} s cap), "
      "each walk flown: shortcut in the scene and checked; "
      "stretch_slack {} from sample {}\n\n",
      options.scene, delta, 1.5 * delta, samples, paper.pois, options.seeds, work.iterations, work.jobs,
      work.cap_seconds, options.stretch_slack, options.stretch_slack_after);

  std::map<std::string, Row> rows;
  std::vector<double> targets;
  std::size_t capped = 0;
  nlohmann::json runs = nlohmann::json::array();
  // The first `seeds` seeds whose roadmaps share a target (a seed whose Dense root is cut off
  // from everything it could see compares nothing); at most 3x as many are tried.
  std::vector<std::uint64_t> used, skipped;
  for (std::uint64_t seed = 1; used.size() < options.seeds && seed <= 3 * options.seeds; ++seed) {
    std::map<std::string, Row> seed_rows;
    nlohmann::json seed_runs = nlohmann::json::array();
    const planning::Scene scene = planning::Scene::build(scene_variant(base, paper.pois, seed, delta));
    planning::BuildOptions build;
    build.seed = seed;
    build.threads = options.threads;
    build.stretch_slack = options.stretch_slack;  // read by the stretch rules only
    build.stretch_slack_after = options.stretch_slack_after;
    std::vector<InspectionGraph> graphs;  // dense, irisc, dense-wide (with --wide), then each rule set
    std::vector<std::vector<Vec3>> positions;
    std::vector<std::string> names{"dense", "irisc"};
    if (options.wide) names.emplace_back("dense-wide");
    const std::size_t baselines = names.size();
    graphs.reserve(rule_sets.size() + baselines);
    graphs.push_back({});  // dense: filled from the first sparse build (same samples, same G_d)
    positions.push_back({});
    planning::IriscBuilder irisc(scene, build);
    irisc.extend(samples);
    graphs.push_back(InspectionGraph::from_roadmap(irisc.roadmap()));
    positions.emplace_back(irisc.roadmap().positions().begin(), irisc.roadmap().positions().end());
    if (options.wide) {
      const planning::Scene wide = planning::Scene::build(scene_variant(base, paper.pois, seed, 3.0 * delta));
      planning::DenseBuilder dense_wide(wide, build);
      dense_wide.extend(samples);
      graphs.push_back(InspectionGraph::from_roadmap(dense_wide.roadmap()));
      positions.emplace_back(dense_wide.roadmap().positions().begin(), dense_wide.roadmap().positions().end());
    }
    for (std::size_t i = 0; i < rule_sets.size(); ++i) {
      planning::SparsBuilder b(scene, build, rule_sets[i]);
      b.extend(samples);
      if (i == 0) {
        graphs[0] = InspectionGraph::from_roadmap(*b.dense());
        positions[0].assign(b.dense()->positions().begin(), b.dense()->positions().end());
      }
      planning::RouteStretchOptions ro;
      ro.big_delta = scene.config().sparse_delta;
      ro.stretch = scene.config().stretch;
      const planning::RouteStretchReport s =
          planning::measure_route_stretch(scene, b.roadmap(), *b.dense(), b.dense_ids(), ro);
      const planning::VerificationReport v =
          planning::verify_sparse_pair(scene, b.roadmap(), *b.dense(), b.dense_ids());
      Row& row = seed_rows[options.rule_sets[i]];
      row.vertices.push_back(static_cast<double>(b.roadmap().vertex_count()));
      row.edges.push_back(static_cast<double>(b.roadmap().edge_count()));
      row.components.push_back(static_cast<double>(b.roadmap().component_count()));
      row.violations.push_back(static_cast<double>(v.invariant_violations + (v.geometry_ok() ? 0 : 1'000'000)));
      row.median3.push_back(s.within_3_delta.vs_dense.median);
      row.p95_3.push_back(s.within_3_delta.vs_dense.p95);
      row.over3.push_back(s.within_3_delta.vs_dense.share_over_t);
      row.segment_median3.push_back(s.within_3_delta.vs_segment.median);
      row.segment_p95_3.push_back(s.within_3_delta.vs_segment.p95);
      for (std::size_t k = 0; k < 3; ++k) row.median_bin[k].push_back(s.bins[k].vs_dense.median);
      row.median_bin[3].push_back(s.beyond_3_delta.vs_dense.median);
      graphs.push_back(InspectionGraph::from_roadmap(b.roadmap()));
      positions.emplace_back(b.roadmap().positions().begin(), b.roadmap().positions().end());
      names.push_back(options.rule_sets[i]);
      nlohmann::json run = to_json(b.admissions());
      run["seed"] = seed;
      run["rule_set"] = options.rule_sets[i];
      run["vertices"] = b.roadmap().vertex_count();
      run["edges"] = b.roadmap().edge_count();
      run["viewpoint_stretch"] = to_json(s);
      seed_runs.push_back(run);
    }
    std::vector<const InspectionGraph*> pointers;
    for (const InspectionGraph& g : graphs) pointers.push_back(&g);
    const std::vector<PoiId> common = common_targets(pointers);
    if (common.empty()) {
      std::cerr << fmt::format("seed {}: no POI is seen from the root in every roadmap; seed skipped\n", seed);
      skipped.push_back(seed);
      continue;
    }
    used.push_back(seed);
    for (auto& [name, row] : seed_rows) {
      Row& all = rows[name];
      const auto append = [](std::vector<double>& to, const std::vector<double>& from) {
        to.insert(to.end(), from.begin(), from.end());
      };
      append(all.vertices, row.vertices);
      append(all.edges, row.edges);
      append(all.components, row.components);
      append(all.violations, row.violations);
      append(all.median3, row.median3);
      append(all.p95_3, row.p95_3);
      append(all.over3, row.over3);
      append(all.segment_median3, row.segment_median3);
      append(all.segment_p95_3, row.segment_p95_3);
      for (std::size_t k = 0; k < 4; ++k) append(all.median_bin[k], row.median_bin[k]);
    }
    for (auto& run : seed_runs) runs.push_back(std::move(run));
    targets.push_back(static_cast<double>(common.size()));
    const std::vector<planning::GipResult> tours = solve_each(pointers, common, seed, work);
    const std::vector<double> flown = flown_costs(scene, pointers, positions, common, tours, names);
    for (std::size_t i = 0; i < tours.size(); ++i) {
      capped += hit_time_cap(tours[i], work);
      Row& row = rows[names[i]];
      row.tour.push_back(tours[i].tour.cost);
      row.tour_ratio.push_back(tours[i].tour.cost / tours[0].tour.cost);
      row.flown.push_back(flown[i]);
      row.flown_ratio.push_back(flown[i] / flown[0]);
      if (options.wide) row.flown_wide_ratio.push_back(flown[i] / flown[2]);
      if (i < baselines) {
        row.vertices.push_back(static_cast<double>(graphs[i].vertex_count()));
        row.edges.push_back(static_cast<double>(graphs[i].edge_count()));
      }
    }
    std::cerr << fmt::format("seed {}: I_t = {}; walk / flown: dense {:.1f} / {:.1f}", seed, common.size(),
                             tours[0].tour.cost, flown[0]);
    for (std::size_t i = 1; i < tours.size(); ++i) {
      std::cerr << fmt::format(", {} {:.1f} / {:.1f}", names[i], tours[i].tour.cost, flown[i]);
    }
    std::cerr << '\n';
  }

  std::cout << fmt::format(
      "Seeds used: {} (skipped, no common target: {}); I_t: {} targets on average; runs stopped by the time cap "
      "before their iterations: {}\n\n",
      fmt::join(used, ", "), skipped.empty() ? std::string("none") : fmt::format("{}", fmt::join(skipped, ", ")),
      mean_cell(targets, 1), capped);
  std::cout << "| roadmap | \\|V\\| | \\|E\\| | components | Inv. 1 violations | stretch vs dense within 3 Delta: "
               "median / p95 / share > t | median by bin [0,1) [1,2) [2,3) [3,inf) Delta | vs segment: median / p95 "
               "| walk | walk / Dense | flown | flown / Dense | flown / Dense-wide |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<std::string> order{"dense", "irisc"};
  if (options.wide) order.emplace_back("dense-wide");
  order.insert(order.end(), options.rule_sets.begin(), options.rule_sets.end());
  nlohmann::json summary = nlohmann::json::array();
  for (const std::string& name : order) {
    const Row& r = rows[name];
    const bool sparse = !r.median3.empty();
    std::cout << fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", name, mean_sd_cell(r.vertices, 0),
        mean_sd_cell(r.edges, 0), sparse ? mean_cell(r.components, 1) : "-", sparse ? mean_cell(r.violations, 0) : "-",
        sparse ? fmt::format("{} / {} / {:.1f}%", mean_cell(r.median3, 3), mean_cell(r.p95_3, 3),
                             100.0 * mean_sd(r.over3).mean)
               : "-",
        sparse ? fmt::format("{} {} {} {}", mean_cell(r.median_bin[0], 3), mean_cell(r.median_bin[1], 3),
                             mean_cell(r.median_bin[2], 3), mean_cell(r.median_bin[3], 3))
               : "-",
        sparse ? fmt::format("{} / {}", mean_cell(r.segment_median3, 3), mean_cell(r.segment_p95_3, 3)) : "-",
        mean_sd_cell(r.tour, 1), mean_cell(r.tour_ratio, 3), mean_sd_cell(r.flown, 1), mean_cell(r.flown_ratio, 3),
        mean_cell(r.flown_wide_ratio, 3));
    summary.push_back(
        {{"roadmap", name},
         {"vertices", mean_sd(r.vertices).mean},
         {"edges", mean_sd(r.edges).mean},
         {"tour", mean_sd(r.tour).mean},
         {"tour_over_dense", mean_sd(r.tour_ratio).mean},
         {"flown", mean_sd(r.flown).mean},
         {"flown_over_dense", mean_sd(r.flown_ratio).mean},
         {"flown_over_dense_wide", options.wide ? nlohmann::json(mean_sd(r.flown_wide_ratio).mean) : nlohmann::json()},
         {"flown_per_seed", r.flown},
         {"median_within_3_Delta", sparse ? mean_sd(r.median3).mean : 0.0},
         {"p95_within_3_Delta", sparse ? mean_sd(r.p95_3).mean : 0.0},
         {"violations", sparse ? mean_sd(r.violations).mean : 0.0}});
  }
  if (options.json) {
    std::cout << nlohmann::json{{"scene", options.scene},
                                {"delta", delta},
                                {"iterations", work.iterations},
                                {"stretch_slack", options.stretch_slack},
                                {"stretch_slack_after", options.stretch_slack_after},
                                {"seeds", used},
                                {"skipped_seeds", skipped},
                                {"summary", summary},
                                {"runs", runs}}
                     .dump()
              << std::endl;
  }
  return 0;
}

CLI::App* add_experiment_ablation_command(CLI::App& parent, ExperimentOptions& options) {
  auto* cmd = parent.add_subcommand(
      "ablation",
      "Sparse-roadmap rules one by one: size, route stretch, Invariant 1 and tours (same targets, same work)");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--scene", options.scene, "water_tower, truss_bridge or caric_city (the paper's setting)");
  cmd->add_option("--seeds", options.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  cmd->add_option("--delta", options.delta, "delta (0: calibrated)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--samples", options.samples, "N (0: the paper's)")->check(CLI::Range(0, 100'000'000));
  cmd->add_option("--rule-sets", options.rule_sets,
                  "Rule sets: alg1 or stretch, then +R / -R with R in join, witness, shortcut")
      ->delimiter(',');
  cmd->add_option("--iterations", options.iterations, "Solver iterations per roadmap")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  cmd->add_option("--cap", options.cap, "Wall-clock cap per tour, seconds")->check(CLI::Range(0.1, 1e5));
  add_stretch_slack_options(*cmd, options.stretch_slack, options.stretch_slack_after);
  cmd->add_flag("--wide", options.wide,
                "Tour Dense-wide too (Dense joined within 2 Delta: the strongest baseline, and the slowest)");
  cmd->add_option("--jobs", options.jobs, "Tours solved at once (one solver thread each)")->check(CLI::Range(1u, 64u));
  return cmd;
}

}  // namespace ispars::lab
