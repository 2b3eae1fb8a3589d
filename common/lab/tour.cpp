// `ispars-lab tour`: an inspection tour on a roadmap file or IRIS files.

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>

#include "commands.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/tour/flown_tour.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "json_output.hpp"

namespace ispars::lab {
namespace {

// POI ids, whitespace-separated; '#' starts a comment.
std::vector<PoiId> read_targets(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw params::InputError(path, "--targets", "cannot open for reading");
  std::vector<PoiId> targets;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    for (std::string word; words >> word;) {
      std::size_t used = 0;
      unsigned long long id = 0;
      try {
        id = std::stoull(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || word[0] == '-' || id > std::numeric_limits<PoiId>::max()) {
        throw params::InputError(path, fmt::format("line {}", number), fmt::format("'{}' is not a POI id", word));
      }
      targets.push_back(static_cast<PoiId>(id));
    }
  }
  if (targets.empty()) throw params::InputError(path, "--targets", "no POI id in the file");
  return targets;
}

// The daemon's pipeline (flown_tour.hpp) on the roadmap, when its scene is given.
std::optional<planning::FlownTour> fly_with_scene(const TourCommandOptions& options, const RoadmapFileGraph& input,
                                                  const planning::GipOptions& search) {
  if (options.scene.empty()) return std::nullopt;
  const planning::Scene scene = planning::Scene::build(scene_files::parse_scene_config(options.scene));
  if (input.positions.empty() || (input.positions[0] - scene.config().root).norm() > 1e-6) {
    throw params::InputError(options.scene, "--scene",
                             "its root is not the roadmap's root (vertex 0): not the roadmap's scene");
  }
  planning::FlownTourOptions flown;
  flown.search = search;
  flown.build_samples = options.build_samples;
  planning::FlownTour t = planning::fly_tour(scene, input.graph, input.positions, flown);
  if (!t.check.valid()) throw std::runtime_error("tour: the flown tour failed its check: " + t.check.problem);
  return t;
}

nlohmann::json stages_json(const std::vector<planning::FlownStage>& stages) {
  nlohmann::json out = nlohmann::json::array();
  for (const planning::FlownStage& s : stages)
    out.push_back({{"stage", s.name}, {"cost", s.cost}, {"seconds", s.seconds}});
  return out;
}

}  // namespace

namespace {

RoadmapFileGraph read_tour_input(const TourCommandOptions& options) {
  if (options.roadmap.empty() == options.iris.empty()) {
    throw params::InputError("tour", "input", "give either a roadmap file or --iris PREFIX");
  }
  if (!options.scene.empty() && !options.iris.empty()) {
    throw params::InputError("tour", "--scene", "shortcuts need a roadmap file's positions; IRIS files have none");
  }
  RoadmapFileGraph input;
  if (!options.iris.empty()) {
    input.graph = InspectionGraph::read_iris(options.iris, options.all_edges);
  } else {
    input = read_roadmap_file_graph(options.roadmap, options.graph);
  }
  return input;
}

// The solver's options; with `live`, its progress shown on one line of stderr.
planning::GipOptions solver_options(const TourCommandOptions& options, bool live) {
  planning::GipOptions solve;
  solve.budget_seconds = options.budget;
  solve.seed = options.seed;
  solve.threads = options.threads;
  solve.max_iterations = options.iterations;
  solve.lp_bound = options.bound == "lp";
  if (!options.targets.empty()) solve.targets = read_targets(options.targets);
  if (!live) return solve;
  // Both callbacks run under the solver's locks, but on different threads.
  auto shown = std::make_shared<std::pair<double, double>>(INFINITY, 0.0);
  auto mutex = std::make_shared<std::mutex>();
  const auto show = [shown, mutex](double t, double cost, double bound) {
    std::lock_guard lock(*mutex);
    if (cost >= 0) shown->first = cost;
    if (bound >= 0) shown->second = bound;
    std::cerr << fmt::format("\r{:8.2f} s  best tour {:.6g}  bound {:.6g}   ", t, shown->first, shown->second)
              << std::flush;
  };
  solve.on_improvement = [show](double t, double cost) { show(t, cost, -1.0); };
  solve.on_bound = [show](double t, double bound) { show(t, -1.0, bound); };
  return solve;
}

// What one tour run found, as the command reports it.
struct TourRun {
  const RoadmapFileGraph& input;
  const planning::GipResult& r;
  const std::optional<planning::FlownTour>& flown;
  nlohmann::json trace = nlohmann::json::array();
};

nlohmann::json summary_json(const TourRun& run) {
  const planning::GipResult& r = run.r;
  const std::optional<planning::FlownTour>& flown = run.flown;
  const planning::ShortcutTour* shortcut = flown ? &flown->roadmap_shortcut : nullptr;
  nlohmann::json bound_trace = nlohmann::json::array();
  for (const auto& [t, b] : r.bound_trace) bound_trace.push_back({t, b});
  const nlohmann::json lower = r.lower_bound ? nlohmann::json(*r.lower_bound) : nlohmann::json();
  const InspectionGraph& graph = run.input.graph;
  return {{"cost", r.tour.cost},
          {"covered", r.tour.covered.size()},
          {"targets", r.targets.size()},
          {"seconds", r.seconds},
          {"lower_bound", lower},
          {"valid", r.validation.valid()},
          {"trace", run.trace},
          {"bound_trace", bound_trace},
          {"bound_complete", r.bound_complete},
          {"bound_rounds", r.bound_rounds},
          {"bound_cuts", r.bound_cuts},
          {"bound_dropped", r.bound_dropped},
          {"bound_peak_nonzeros", r.bound_peak_nonzeros},
          {"bound_note", r.bound_note},
          {"gap", r.lower_bound && r.tour.cost > 0 ? (r.tour.cost - *r.lower_bound) / r.tour.cost : 0.0},
          {"walk_steps", r.tour.walk.size() - 1},
          {"shortcut_cost", shortcut ? nlohmann::json(shortcut->cost) : nlohmann::json()},
          {"shortcut_steps", shortcut ? shortcut->stops.size() - 1 : 0},
          {"shortcut_segments_checked", shortcut ? shortcut->segments_checked : 0},
          {"flown_cost", flown ? nlohmann::json(flown->cost) : nlohmann::json()},
          {"flown_steps", flown ? flown->stops.size() - 1 : 0},
          {"stages", flown ? stages_json(flown->stages) : nlohmann::json::array()},
          {"graph_vertices", flown ? flown->graph_vertices : graph.vertex_count()},
          {"graph_edges", flown ? flown->graph_edges : graph.edge_count()},
          {"candidates", r.candidates},
          {"iterations", r.iterations},
          {"vertices", graph.vertex_count()},
          {"edges", graph.edge_count()}};
}

// The tour file (--out): the walk, and with positions what render draws.
void write_tour_file(const std::string& out, const TourRun& run) {
  const planning::GipResult& r = run.r;
  nlohmann::json file = {{"cost", r.tour.cost},  {"walk", r.tour.walk},           {"covered", r.tour.covered},
                         {"targets", r.targets}, {"valid", r.validation.valid()}, {"trace", run.trace}};
  if (!run.input.positions.empty()) {
    nlohmann::json positions = nlohmann::json::array();
    for (const VertexId v : r.tour.walk) positions.push_back(to_json(run.input.positions[v]));
    file["positions"] = std::move(positions);
    nlohmann::json path = nlohmann::json::array();  // what render draws: the flown tour, or the walk
    if (run.flown) {
      for (const Vec3& p : run.flown->stops) path.push_back(to_json(p));
    } else {
      path = file["positions"];
    }
    file["path"] = std::move(path);
  }
  std::ofstream f(out);
  if (!f) throw params::InputError(out, "--out", "cannot open for writing");
  f << file.dump() << '\n';
  if (!f) throw params::InputError(out, "--out", "write failed");
}

void print_summary(const TourRun& run) {
  const planning::GipResult& r = run.r;
  const std::optional<planning::FlownTour>& flown = run.flown;
  std::cout << fmt::format("graph: {} vertices, {} edges; {} targets, {} candidate vertices\n",
                           run.input.graph.vertex_count(), run.input.graph.edge_count(), r.targets.size(),
                           r.candidates);
  std::cout << fmt::format("tour: cost {:.6g}, {} steps, covers {}/{} targets, {}\n", r.tour.cost,
                           r.tour.walk.size() - 1, r.tour.covered.size(), r.targets.size(),
                           r.validation.valid() ? "valid" : "INVALID: " + r.validation.problem);
  if (flown) {
    const planning::ShortcutTour& shortcut = flown->roadmap_shortcut;
    std::cout << fmt::format("shortcut tour: cost {:.6g} ({:.1f}% shorter), {} straight steps\n", shortcut.cost,
                             100.0 * (1.0 - shortcut.cost / r.tour.cost), shortcut.stops.size() - 1);
    std::cout << fmt::format(
        "flown tour: cost {:.6g} ({:.1f}% shorter than the walk), {} straight steps, searched "
        "last on {} vertices and {} edges, {} segments checked\n",
        flown->cost, 100.0 * (1.0 - flown->cost / r.tour.cost), flown->stops.size() - 1, flown->graph_vertices,
        flown->graph_edges, flown->segments_checked);
  }
  if (r.lower_bound) {
    std::cout << fmt::format("proven lower bound {:.6g} (gap {:.1f}%){}\n", *r.lower_bound,
                             100.0 * (r.tour.cost - *r.lower_bound) / r.tour.cost,
                             r.bound_complete ? ", the LP solved over all its cuts"
                             : !r.bound_note.empty()
                                 ? "; no LP bound: " + r.bound_note
                                 : fmt::format(", LP after {} rounds and {} cuts", r.bound_rounds, r.bound_cuts));
  }
  std::cout << fmt::format("{} improvements in {:.2f} s, {} search iterations\n", r.trace.size(), r.seconds,
                           r.iterations);
}

}  // namespace

int run_tour(const TourCommandOptions& options) {
  const RoadmapFileGraph input = read_tour_input(options);
  const bool live = !options.json && ::isatty(STDERR_FILENO);
  const planning::GipOptions solve = solver_options(options, live);
  const std::optional<planning::FlownTour> flown = fly_with_scene(options, input, solve);
  const planning::GipResult r = flown ? flown->search : planning::solve_gip(input.graph, solve);
  if (live) std::cerr << '\n';
  TourRun run{input, r, flown};
  for (const auto& [t, c] : r.trace) run.trace.push_back({t, c});
  if (!options.out.empty()) write_tour_file(options.out, run);
  if (options.json) {
    std::cout << summary_json(run).dump() << std::endl;
  } else {
    print_summary(run);
  }
  return r.validation.valid() ? 0 : 1;
}

CLI::App* add_tour_command(CLI::App& parent, TourCommandOptions& options) {
  auto* cmd = parent.add_subcommand("tour", "An inspection tour (GIP) on a roadmap file or IRIS files");
  cmd->add_option("roadmap", options.roadmap, "Roadmap JSON (ispars-lab build --out, ispars snapshot --out)");
  cmd->add_option("--graph", options.graph, "Which graph of the file")->check(CLI::IsMember({"roadmap", "dense"}));
  cmd->add_option("--iris", options.iris, "IRIS files PREFIX_vertex and PREFIX_edge instead of a roadmap file");
  cmd->add_flag("--all-edges", options.all_edges,
                "IRIS: keep edges marked invalid (as the published solver read them)");
  cmd->add_option("--budget", options.budget, "Seconds of search")->required()->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--seed", options.seed, "Seed");
  cmd->add_option("--threads", options.threads, "Search threads (one chain each)")->check(CLI::Range(1u, 64u));
  cmd->add_option("--iterations", options.iterations,
                  "Stop after this many search iterations per thread (deterministic)");
  cmd->add_option("--targets", options.targets, "A file of target POI ids (default: all seen from the root)");
  cmd->add_option("--bound", options.bound, "lp: prove a lower bound by linear programming beside the search; simple")
      ->check(CLI::IsMember({"lp", "simple"}));
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  cmd->add_option("--out", options.out, "Write the tour (walk, positions, trace, path: what render draws) as JSON");
  cmd->add_option("--scene", options.scene,
                  "The roadmap's scene YAML: fly the tour as the daemon does (shortcut, corridor, refinement, "
                  "checked; the budget is the whole pipeline's)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--build-samples", options.build_samples,
                  "With --scene: the samples the roadmap was built from, for the corridor's density (0: no corridor)");
  return cmd;
}

}  // namespace ispars::lab
