// `ispars-lab experiment anytime`: the paper's Fig. 4. For each scene and seed, Dense,
// Inspection-SPARS and IRIS-C roadmaps (calibrated as in Table II), the common target set I_t
// (POIs seen from the root's component in all three), and the same GIP solver with the same
// budget on each: mean +- sd of the best tour against time; a CSV, a PNG and a summary table.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <map>
#include <mutex>
#include <thread>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "ispars/gip_solver.hpp"
#include "ispars/inspection_graph.hpp"

namespace ispars::lab {
namespace {

struct AnytimeScene {
  const char* name;
  std::size_t samples;
  std::size_t pois;
  double paper_degree;
};

const std::vector<AnytimeScene>& anytime_scenes() {
  static const std::vector<AnytimeScene> scenes{{"water_tower", 4000, 100, 2.0 * 14474 / 3933},
                                                {"truss_bridge", 5000, 500, 2.0 * 27508 / 4955},
                                                {"caric_city", 7000, 500, 2.0 * 16891 / 6391}};
  return scenes;
}

const std::vector<BuildMethod>& anytime_methods() {
  static const std::vector<BuildMethod> methods{BuildMethod::dense, BuildMethod::ispars, BuildMethod::irisc};
  return methods;
}

// The best cost found by time t (NaN before the first tour).
double best_at(const std::vector<std::pair<double, double>>& trace, double t) {
  double best = std::nan("");
  for (const auto& [when, cost] : trace) {
    if (when <= t) best = cost;
  }
  return best;
}

std::vector<PoiId> seen_from_root(const InspectionGraph& g) {
  std::vector<char> seen(g.poi_count(), 0);
  for (const VertexId v : g.component_of(0)) {
    for (const PoiId p : g.visible(v)) seen[p] = 1;
  }
  std::vector<PoiId> out;
  for (PoiId p = 0; p < g.poi_count(); ++p) {
    if (seen[p]) out.push_back(p);
  }
  return out;
}

void plot(const std::string& csv, const std::string& png, double budget) {
  std::ostringstream script;
  script << "set terminal pngcairo size 1500,500 font 'Sans,11'\nset termoption noenhanced\n"
         << "set output '" << png << "'\nset datafile separator ','\n"
         << "set multiplot layout 1,3 title 'Best tour against solver time (mean +- sd over seeds; same solver and budget "
         << budget << " s per roadmap)'\n"
         << "set key right top\nset grid\nset xlabel 'solver time [s]'\nset ylabel 'tour length [m]'\n";
  for (const AnytimeScene& s : anytime_scenes()) {
    script << "set title '" << s.name << "'\nplot ";
    bool first = true;
    for (const BuildMethod m : anytime_methods()) {
      if (!first) script << ", ";
      first = false;
      const std::string sel = fmt::format("(strcol(1) eq '{}' && strcol(2) eq '{}' ? ", s.name, to_string(m));
      script << "'" << csv << "' skip 1 using 3:" << sel << "$4 : 1/0):" << sel << "$5 : 1/0) with yerrorlines title '"
             << to_string(m) << "'";
    }
    script << "\n";
  }
  script << "unset multiplot\n";
  run_gnuplot(png, script.str());
}

}  // namespace

int run_experiment_anytime(const ExperimentOptions& options) {
  const double budget = options.budget;
  std::cout << fmt::format(
      "# Fig. 4, reproduced: tours within a fixed solver budget ({} seeds, {} s per roadmap, 1 solver thread; "
      "command: ispars-lab experiment anytime --seeds {} --budget {} --jobs {})\n\n",
      options.seeds, budget, options.seeds, budget, options.jobs);
  std::ofstream csv(options.csv.empty() ? "/dev/null" : options.csv);
  csv << "scene,method,seconds,mean_cost,sd_cost,seeds_with_tour\n";
  nlohmann::json results = nlohmann::json::array();
  std::cout << "| scene | I_t (mean) | method | \\|V\\| | best tour, mean +- sd | Inspection-SPARS's tour against it | first tour at [s] |\n"
               "|---|---|---|---|---|---|---|\n";
  for (const AnytimeScene& as : anytime_scenes()) {
    const SceneConfig base = parse_scene_config(options.scenes_dir + "/" + as.name + ".yaml");
    const double delta = calibrate_delta(base, as.samples, as.paper_degree, options.threads);
    // traces[method][seed]
    std::map<BuildMethod, std::vector<std::vector<std::pair<double, double>>>> traces;
    std::map<BuildMethod, std::vector<double>> finals, firsts, sizes;
    std::vector<double> target_counts;
    for (std::uint64_t seed = 1; seed <= options.seeds; ++seed) {
      const Scene scene = Scene::build(scene_variant(base, as.pois, seed, delta));
      std::map<BuildMethod, InspectionGraph> graphs;
      for (const BuildMethod m : anytime_methods()) {
        BuildOptions build;
        build.seed = seed;
        build.threads = options.threads;
        const auto builder = make_roadmap_builder(m, scene, build);
        builder->extend(as.samples);
        graphs.emplace(m, InspectionGraph::from_roadmap(builder->roadmap()));
        sizes[m].push_back(static_cast<double>(builder->roadmap().vertex_count()));
      }
      // I_t: POIs seen from the root's component of every roadmap.
      std::vector<PoiId> common = seen_from_root(graphs.at(anytime_methods().front()));
      for (const BuildMethod m : anytime_methods()) {
        const std::vector<PoiId> mine = seen_from_root(graphs.at(m));
        std::vector<PoiId> both;
        std::set_intersection(common.begin(), common.end(), mine.begin(), mine.end(), std::back_inserter(both));
        common = std::move(both);
      }
      // Solve the three on up to `jobs` cores at once, one solver thread each.
      std::vector<std::thread> pool;
      std::mutex mutex;
      std::size_t next = 0;
      std::map<BuildMethod, GipResult> solved;
      std::string failure;
      const auto work = [&] {
        for (;;) try {
          BuildMethod m;
          {
            std::lock_guard lock(mutex);
            if (next >= anytime_methods().size()) return;
            m = anytime_methods()[next++];
          }
          GipOptions solve;
          solve.targets = common;
          solve.budget_seconds = budget;
          solve.seed = seed;
          GipResult r = solve_gip(graphs.at(m), solve);
          if (!r.validation.valid()) throw std::runtime_error("invalid tour: " + r.validation.problem);
          std::lock_guard lock(mutex);
          solved.emplace(m, std::move(r));
        } catch (const std::exception& e) {
          std::lock_guard lock(mutex);
          failure = e.what();
          next = anytime_methods().size();
          return;
        }
      };
      if (common.empty()) {
        std::cerr << fmt::format("{} seed {}: no POI is seen from the root in all three roadmaps; seed skipped\n",
                                 as.name, seed);
        for (const BuildMethod m : anytime_methods()) sizes[m].pop_back();
        continue;
      }
      target_counts.push_back(static_cast<double>(common.size()));
      for (unsigned j = 1; j < options.jobs; ++j) pool.emplace_back(work);
      work();
      for (auto& t : pool) t.join();
      if (!failure.empty()) throw std::runtime_error(fmt::format("{} seed {}: {}", as.name, seed, failure));
      for (const BuildMethod m : anytime_methods()) {
        const GipResult& r = solved.at(m);
        traces[m].push_back(r.trace);
        finals[m].push_back(r.tour.cost);
        firsts[m].push_back(r.trace.empty() ? budget : r.trace.front().first);
        results.push_back({{"scene", as.name}, {"seed", seed}, {"method", to_string(m)}, {"targets", common.size()},
                           {"vertices", graphs.at(m).vertex_count()}, {"cost", r.tour.cost},
                           {"lower_bound", r.lower_bound.value_or(0.0)}, {"iterations", r.iterations}});
      }
      std::cerr << fmt::format("{} seed {}: I_t = {}; dense {:.1f}, ispars {:.1f}, irisc {:.1f}\n", as.name, seed,
                               common.size(), solved.at(BuildMethod::dense).tour.cost,
                               solved.at(BuildMethod::ispars).tour.cost, solved.at(BuildMethod::irisc).tour.cost);
    }
    for (const BuildMethod m : anytime_methods()) {
      for (int k = 0; k <= 100; ++k) {
        const double t = budget * k / 100.0;
        std::vector<double> values;
        for (const auto& trace : traces[m]) {
          const double v = best_at(trace, t);
          if (!std::isnan(v)) values.push_back(v);
        }
        if (values.size() != traces[m].size()) continue;  // plot once every seed has a tour
        const MeanSd ms = mean_sd(values);
        csv << fmt::format("{},{},{:.3f},{:.4f},{:.4f},{}\n", as.name, to_string(m), t, ms.mean, ms.sd, values.size());
      }
      const MeanSd f = mean_sd(finals[m]);
      const MeanSd ref = mean_sd(finals[BuildMethod::ispars]);
      std::cout << fmt::format("| {} | {:.1f} | {} | {:.0f} | {:.1f} +- {:.1f} | {} | {:.2f} |\n", as.name,
                               mean_sd(target_counts).mean, to_string(m), mean_sd(sizes[m]).mean, f.mean, f.sd,
                               m == BuildMethod::ispars ? std::string("-")
                                                        : fmt::format("{:+.1f}%", 100.0 * (ref.mean - f.mean) / f.mean),
                               mean_sd(firsts[m]).mean);
    }
  }
  csv.close();
  if (!options.csv.empty() && !options.png.empty()) plot(options.csv, options.png, budget);
  if (options.json) std::cout << nlohmann::json{{"runs", results}}.dump() << std::endl;
  return 0;
}

}  // namespace ispars::lab
