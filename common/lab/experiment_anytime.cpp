// `ispars-lab experiment anytime`: the paper's Fig. 4. For each scene and seed: Dense,
// Inspection-SPARS (the default rule set and the literal Alg. 1) and IRIS-C roadmaps,
// calibrated as in Table II, and Dense-wide (the same samples joined within 2 Delta, the reach
// of a sparse edge); the common target set I_t (POIs seen from the root's component in all of
// them); and the same GIP solver with the same work on each (an iteration cap, one solver
// thread per roadmap). Every tour is also shortcut with the scene's collision checker
// (tour_shortcut.hpp), as a robot would fly it. Also Dense routing with each sparse roadmap's
// viewpoints, which splits a sparse roadmap's loss into "viewpoints lost" and "routing lost".
// Prints a summary table; writes the best tour against time (CSV, PNG) and every run (JSON).

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/dense_builder.hpp"
#include "ispars/planning/builders/irisc_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "tour_support.hpp"

namespace ispars::lab {
namespace {

// The roadmaps of one seed, in this order; the last two are Dense routing with the viewpoints
// of the two sparse roadmaps.
const std::vector<std::string>& roadmap_names() {
  static const std::vector<std::string> names{
      "dense", "ispars", "ispars-alg1", "irisc", "dense-wide", "dense/ispars-viewpoints", "dense/alg1-viewpoints"};
  return names;
}
constexpr std::size_t kPlotted = 5;  // the first five are the figure's curves (the methods)

// The best cost found by time t (NaN before the first tour).
double best_at(const std::vector<std::pair<double, double>>& trace, double t) {
  double best = std::nan("");
  for (const auto& [when, cost] : trace) {
    if (when <= t) best = cost;
  }
  return best;
}

void plot(const std::string& csv, const std::string& png, const std::string& work) {
  // Per scene: the mean as a line and mean +- sd as a band; x is selected with y so that each
  // panel scales to its own scene's times.
  std::ostringstream script;
  script << "set terminal pngcairo size 1500,500 font 'Sans,11'\nset termoption noenhanced\n"
         << "set output '" << png << "'\nset datafile separator ','\n"
         << "set multiplot layout 1,3 title 'Best tour against solver time (mean, band +- sd over seeds; " << work
         << ")'\n"
         << "set key right top\nset grid\nset logscale x\nset xlabel 'solver time [s] (log)'\n"
         << "set ylabel 'tour length'\nset style fill transparent solid 0.15 noborder\n";
  const char* colours[] = {"#7b3294", "#1b9e77", "#56b4e9", "#e69f00", "#d7191c"};
  for (const PaperSetting& s : paper_settings()) {
    script << "set title '" << s.scene << "'\nplot ";
    for (std::size_t m = 0; m < kPlotted; ++m) {
      if (m > 0) script << ", ";
      const std::string sel =
          fmt::format("(strcol(1) eq '{}' && strcol(2) eq '{}' && $3 > 0 ? ", s.scene, roadmap_names()[m]);
      script << "'" << csv << "' skip 1 using " << sel << "$3 : 1/0):($4 - $5):($4 + $5) with filledcurves lc rgb '"
             << colours[m] << "' notitle, '" << csv << "' skip 1 using " << sel
             << "$3 : 1/0):4 with lines lw 2 lc rgb '" << colours[m] << "' title '" << roadmap_names()[m] << "'";
    }
    script << "\n";
  }
  script << "unset multiplot\n";
  run_gnuplot(png, script.str());
}

struct Runs {
  std::vector<std::vector<std::pair<double, double>>> traces;
  std::vector<double> vertices, edges, costs, over_dense, over_irisc, first, seconds, violations, bounds, gaps;
  std::vector<double> shortcut, shortcut_over_best_other;  // the shortcut tours, and / the best other method's
  std::vector<double> rounds, bound_seconds;               // the LP's solves and wall time
  std::string skipped;                                     // why an LP was not attempted, if one was not
  std::size_t complete = 0;                                // bounds solved over all their cuts
};

// Each tour shortcut with the scene's collision checker; positions[i] places graphs[i]'s vertices.
std::vector<planning::ShortcutTour> shortcut_each(std::span<const InspectionGraph> graphs,
                                                  const std::vector<std::span<const Vec3>>& positions,
                                                  const std::vector<PoiId>& targets,
                                                  const std::vector<planning::GipResult>& tours,
                                                  const planning::Scene& scene) {
  const planning::SegmentValid valid = [&scene](const Vec3& a, const Vec3& b) { return scene.segment_valid(a, b); };
  std::vector<planning::ShortcutTour> out;
  for (std::size_t i = 0; i < graphs.size(); ++i) {
    out.push_back(planning::shortcut_tour(graphs[i], positions[i], targets, tours[i].tour, valid));
    const planning::ShortcutValidation check =
        planning::check_shortcut_tour(graphs[i], positions[i], 0, targets, out.back(), valid);
    if (!check.valid()) throw std::runtime_error("a shortcut tour failed its check: " + check.problem);
  }
  return out;
}

// For each method (the first kPlotted), its shortcut tour over the best other method's.
std::vector<double> over_best_other(const std::vector<planning::ShortcutTour>& shortcuts) {
  std::vector<double> ratio;
  for (std::size_t i = 0; i < kPlotted; ++i) {
    double best = INFINITY;
    for (std::size_t j = 0; j < kPlotted; ++j) {
      if (j != i) best = std::min(best, shortcuts[j].cost);
    }
    ratio.push_back(shortcuts[i].cost / best);
  }
  return ratio;
}

// One row of the summary table: roadmap m's figures over the seeds of one scene.
std::string summary_row(const std::string& scene, double targets, std::size_t m, const Runs& run) {
  const bool sparse = m == 1 || m == 2;
  return fmt::format(
      "| {} | {:.1f} | {} | {:.0f} | {:.0f} | {} | {:.3f} | {:.3f} | {} | {} | {} | {} | {:.2f} "
      "| {:.1f} |\n",
      scene, targets, roadmap_names()[m], mean_sd(run.vertices).mean, mean_sd(run.edges).mean,
      mean_sd_cell(run.costs, 1), mean_sd(run.over_dense).mean, mean_sd(run.over_irisc).mean,
      mean_sd_cell(run.shortcut, 1),
      run.shortcut_over_best_other.empty()
          ? std::string("-")
          : fmt::format("{:.3f} (max {:.3f})", mean_sd(run.shortcut_over_best_other).mean,
                        *std::max_element(run.shortcut_over_best_other.begin(), run.shortcut_over_best_other.end())),
      !run.skipped.empty() ? "no LP on some seeds: " + run.skipped
      : run.bounds.empty() ? std::string("-")
                           : fmt::format("{:.1f} ({:.1f}%; {}/{}; {:.0f}, {:.1f})", mean_sd(run.bounds).mean,
                                         100.0 * mean_sd(run.gaps).mean, run.complete, run.bounds.size(),
                                         mean_sd(run.rounds).mean, mean_sd(run.bound_seconds).mean),
      sparse ? fmt::format("{:.0f}", mean_sd(run.violations).mean * run.violations.size()) : std::string("-"),
      mean_sd(run.first).mean, mean_sd(run.seconds).mean);
}

}  // namespace

int run_experiment_anytime(const ExperimentOptions& options) {
  if (options.replot) {
    if (options.csv.empty() || options.png.empty()) {
      throw params::InputError("experiment anytime", "--replot", "needs --csv (to read) and --png (to write)");
    }
    plot(options.csv, options.png, "replotted from " + options.csv);
    return 0;
  }
  const SolverWork work{options.iterations, options.iterations > 0 ? options.cap : options.budget, options.jobs};
  const std::string work_text =
      work.iterations > 0
          ? fmt::format(
                "{} solver iterations per roadmap, one solver thread each, {} roadmaps at a time, {:.0f} s cap; "
                "LP bound {:.0f} s per roadmap",
                work.iterations, work.jobs, work.cap_seconds, options.bound_seconds)
          : fmt::format("{:.0f} s per roadmap, one solver thread each, {} roadmaps at a time", work.cap_seconds,
                        work.jobs);
  std::cout << fmt::format("# Fig. 4, reproduced: {} seeds; the same work for every roadmap: {}\n\n", options.seeds,
                           work_text);
  std::ofstream csv(options.csv.empty() ? "/dev/null" : options.csv);
  csv << "scene,method,seconds,mean_cost,sd_cost,seeds_with_tour\n";
  nlohmann::json results = nlohmann::json::array();
  std::ostringstream summary, per_seed, notes;
  summary << "| scene | I_t (mean) | roadmap | \\|V\\| | \\|E\\| | best tour, mean +- sd | / Dense | / IRIS-C "
             "| shortcut tour, mean +- sd | shortcut / best other method's "
             "| proven bound on roadmap tours, mean (gap; LPs complete; LP rounds, s) | Inv. 1 violations "
             "| first tour [s] | solver seconds |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  per_seed << "| scene | seed | I_t |";
  for (const std::string& n : roadmap_names()) per_seed << ' ' << n << " |";
  per_seed << "\n|---|---|---|";
  for (std::size_t i = 0; i < roadmap_names().size(); ++i) per_seed << "---|";
  per_seed << '\n';
  std::size_t capped = 0;
  for (const PaperSetting& ps : paper_settings()) {
    const scene_files::SceneConfig base =
        scene_files::parse_scene_config(options.scenes_dir + "/" + ps.scene + ".yaml");
    const double delta = calibrate_delta(base, ps.samples, ps.degree, options.threads);
    std::map<std::string, Runs> runs;
    std::vector<double> target_counts, dropped;
    double longest = 0.0;
    // The first `seeds` seeds whose roadmaps share a target; at most 3x as many are tried.
    std::vector<std::uint64_t> used, skipped;
    for (std::uint64_t seed = 1; used.size() < options.seeds && seed <= 3 * options.seeds; ++seed) {
      const planning::Scene scene = planning::Scene::build(scene_variant(base, ps.pois, seed, delta));
      planning::BuildOptions build;
      build.seed = seed;
      build.threads = options.threads;
      planning::SparsBuilder stretch(scene, build, planning::SparsRules::for_variant(SparsVariant::stretch, true));
      planning::SparsBuilder alg1(scene, build, planning::SparsRules::for_variant(SparsVariant::alg1, true));
      planning::IriscBuilder irisc(scene, build);
      stretch.extend(ps.samples);
      alg1.extend(ps.samples);
      irisc.extend(ps.samples);
      // Dense-wide: the same sample stream, joined within 2 Delta = 3 delta (a sparse edge's reach).
      const planning::Scene wide_scene = planning::Scene::build(scene_variant(base, ps.pois, seed, 3.0 * delta));
      planning::DenseBuilder wide(wide_scene, build);
      wide.extend(ps.samples);
      const Roadmap& dense = *stretch.dense();  // both sparse builders drew the same G_d
      const std::vector<InspectionGraph> graphs{
          InspectionGraph::from_roadmap(dense),          InspectionGraph::from_roadmap(stretch.roadmap()),
          InspectionGraph::from_roadmap(alg1.roadmap()), InspectionGraph::from_roadmap(irisc.roadmap()),
          InspectionGraph::from_roadmap(wide.roadmap()), with_viewpoints(dense, stretch.dense_ids()),
          with_viewpoints(dense, alg1.dense_ids())};
      const std::vector<std::span<const Vec3>> positions{dense.positions(),          stretch.roadmap().positions(),
                                                         alg1.roadmap().positions(), irisc.roadmap().positions(),
                                                         wide.roadmap().positions(), dense.positions(),
                                                         dense.positions()};
      std::vector<double> violations(graphs.size(), 0.0);
      violations[1] = static_cast<double>(
          planning::verify_sparse_pair(scene, stretch.roadmap(), dense, stretch.dense_ids()).invariant_violations);
      violations[2] = static_cast<double>(
          planning::verify_sparse_pair(scene, alg1.roadmap(), dense, alg1.dense_ids()).invariant_violations);
      std::vector<const InspectionGraph*> pointers;
      for (const InspectionGraph& g : graphs) pointers.push_back(&g);
      // I_t: the paper's (over the roadmaps proper), less the few POIs that Dense's root
      // component sees only through viewpoints outside it when restricted to sparse viewpoints
      // (a sparse viewpoint is within Delta > delta, possibly in another dense component).
      const std::size_t paper_targets =
          common_targets(std::span<const InspectionGraph* const>(pointers.data(), kPlotted)).size();
      const std::vector<PoiId> common = common_targets(pointers);
      if (common.empty()) {
        std::cerr << fmt::format("{} seed {}: no POI is seen from the root in every roadmap; seed skipped\n", ps.scene,
                                 seed);
        skipped.push_back(seed);
        continue;
      }
      used.push_back(seed);
      dropped.push_back(static_cast<double>(paper_targets - common.size()));
      target_counts.push_back(static_cast<double>(common.size()));
      const std::vector<planning::GipResult> tours = solve_each(pointers, common, seed, work);
      const std::vector<planning::ShortcutTour> shortcuts = shortcut_each(graphs, positions, common, tours, scene);
      const std::vector<double> shortcut_ratio = over_best_other(shortcuts);
      // The proven LP bound of the four roadmaps, on the same targets: it tells "the search got
      // stuck" (a gap) from "the roadmap holds no better tour" (none).
      const std::vector<planning::TourBoundResult> bounds =
          options.bound_seconds > 0.0 ? bound_each(std::span<const InspectionGraph* const>(pointers.data(), kPlotted),
                                                   common, options.bound_seconds, work.jobs)
                                      : std::vector<planning::TourBoundResult>(kPlotted);
      per_seed << fmt::format("| {} | {} | {} |", ps.scene, seed, common.size());
      for (std::size_t i = 0; i < graphs.size(); ++i) {
        const planning::GipResult& r = tours[i];
        capped += hit_time_cap(r, work);
        Runs& run = runs[roadmap_names()[i]];
        run.traces.push_back(r.trace);
        run.vertices.push_back(static_cast<double>(graphs[i].vertex_count()));
        run.edges.push_back(static_cast<double>(graphs[i].edge_count()));
        run.costs.push_back(r.tour.cost);
        run.shortcut.push_back(shortcuts[i].cost);
        if (i < kPlotted) run.shortcut_over_best_other.push_back(shortcut_ratio[i]);
        run.over_dense.push_back(r.tour.cost / tours[0].tour.cost);
        run.over_irisc.push_back(r.tour.cost / tours[3].tour.cost);
        run.first.push_back(r.trace.empty() ? r.seconds : r.trace.front().first);
        run.seconds.push_back(r.seconds);
        run.violations.push_back(violations[i]);
        if (i < kPlotted && options.bound_seconds > 0.0 && !bounds[i].skipped.empty()) {
          run.skipped = bounds[i].skipped;  // e.g. over the LP's edge limit: no bound, not a bound of 0
        } else if (i < kPlotted && options.bound_seconds > 0.0) {
          run.bounds.push_back(bounds[i].bound);
          // The bound is on the roadmap's tours; a shortcut tour leaves the roadmap and may beat it.
          run.gaps.push_back((r.tour.cost - bounds[i].bound) / r.tour.cost);
          run.complete += bounds[i].complete;
          run.rounds.push_back(static_cast<double>(bounds[i].rounds));
          run.bound_seconds.push_back(bounds[i].seconds);
        }
        longest = std::max(longest, r.seconds);
        per_seed << fmt::format(" {:.1f} / {:.1f} |", r.tour.cost, shortcuts[i].cost);
        results.push_back({{"scene", ps.scene},
                           {"seed", seed},
                           {"roadmap", roadmap_names()[i]},
                           {"targets", common.size()},
                           {"vertices", graphs[i].vertex_count()},
                           {"edges", graphs[i].edge_count()},
                           {"cost", r.tour.cost},
                           {"seconds", r.seconds},
                           {"shortcut_cost", shortcuts[i].cost},
                           {"shortcut_steps", shortcuts[i].stops.size() - 1},
                           {"shortcut_segments_checked", shortcuts[i].segments_checked},
                           {"bound_rounds", i < kPlotted ? bounds[i].rounds : 0},
                           {"bound_seconds", i < kPlotted ? bounds[i].seconds : 0.0},
                           {"iterations", r.iterations},
                           {"invariant_violations", violations[i]},
                           {"trace", r.trace},
                           {"lower_bound", i < kPlotted ? nlohmann::json(bounds[i].bound) : nlohmann::json()},
                           {"bound_complete", i < kPlotted && bounds[i].complete}});
      }
      per_seed << '\n';
      std::cerr << fmt::format(
          "{} seed {}: I_t = {}; tour / shortcut: dense {:.1f} / {:.1f}, ispars {:.1f} / {:.1f}, "
          "alg1 {:.1f} / {:.1f}, irisc {:.1f} / {:.1f}, dense-wide {:.1f} / {:.1f}\n",
          ps.scene, seed, common.size(), tours[0].tour.cost, shortcuts[0].cost, tours[1].tour.cost, shortcuts[1].cost,
          tours[2].tour.cost, shortcuts[2].cost, tours[3].tour.cost, shortcuts[3].cost, tours[4].tour.cost,
          shortcuts[4].cost);
    }
    notes << fmt::format("{}: seeds {} (skipped, no common target: {})\n", ps.scene, fmt::join(used, ", "),
                         skipped.empty() ? std::string("none") : fmt::format("{}", fmt::join(skipped, ", ")));
    notes << fmt::format(
        "{}: calibrated delta {:.3f}; the paper's I_t less the targets the viewpoint-restricted Dense "
        "graphs do not reach from the root: {:.1f} on average (at most {:.0f})\n",
        ps.scene, delta, mean_sd(dropped).mean,
        dropped.empty() ? 0.0 : *std::max_element(dropped.begin(), dropped.end()));
    for (std::size_t m = 0; m < roadmap_names().size(); ++m) {
      const Runs& run = runs[roadmap_names()[m]];
      if (m < kPlotted) {
        for (int k = 0; k <= 100; ++k) {
          const double t = longest * k / 100.0;
          std::vector<double> values;
          for (const auto& trace : run.traces) {
            const double v = best_at(trace, t);
            if (!std::isnan(v)) values.push_back(v);
          }
          if (values.empty() || values.size() != run.traces.size()) continue;  // once every seed has a tour
          const MeanSd ms = mean_sd(values);
          csv << fmt::format("{},{},{:.3f},{:.4f},{:.4f},{}\n", ps.scene, roadmap_names()[m], t, ms.mean, ms.sd,
                             values.size());
        }
      }
      summary << summary_row(ps.scene, mean_sd(target_counts).mean, m, run);
    }
  }
  csv.close();
  std::cout << summary.str() << fmt::format("\nRuns stopped by the time cap before their iterations: {}\n\n", capped)
            << notes.str() << '\n'
            << "Per seed (best tour):\n\n"
            << per_seed.str();
  if (!options.csv.empty() && !options.png.empty()) plot(options.csv, options.png, work_text);
  if (options.json) std::cout << nlohmann::json{{"runs", results}}.dump() << std::endl;
  return 0;
}

CLI::App* add_experiment_anytime_command(CLI::App& parent, ExperimentOptions& options) {
  auto* cmd = parent.add_subcommand(
      "anytime", "Fig. 4: best tour against solver time on Dense, Inspection-SPARS and IRIS-C roadmaps");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--seeds", options.seeds, "Seeds 1..S")->check(CLI::Range(1, 1000));
  cmd->add_option("--iterations", options.iterations,
                  "Solver iterations per roadmap: the same work for each (0: a time budget instead)")
      ->check(CLI::Range(std::uint64_t{0}, std::uint64_t{100'000'000}));
  cmd->add_option("--budget", options.budget, "With --iterations 0: solver seconds per roadmap (the paper: 150)")
      ->check(CLI::Range(0.1, 1e5));
  cmd->add_option("--cap", options.cap, "With --iterations: wall-clock cap per tour, seconds")
      ->check(CLI::Range(0.1, 1e5));
  cmd->add_option("--jobs", options.jobs, "Roadmaps solved at once (one solver thread each)")
      ->check(CLI::Range(1u, 64u));
  cmd->add_option("--csv", options.csv, "CSV of mean +- sd of the best tour against time");
  cmd->add_option("--png", options.png, "Plot (gnuplot)");
  cmd->add_flag("--replot", options.replot, "Only draw --png from the --csv of an earlier run");
  cmd->add_option("--bound-seconds", options.bound_seconds, "Seconds of LP lower bound per roadmap (0: none)")
      ->check(CLI::Range(0.0, 1e5));
  return cmd;
}

}  // namespace ispars::lab
