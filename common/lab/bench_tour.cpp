// `ispars-lab bench tour`: the tour solver on a large roadmap built in memory. Reports the first
// tour's time, whether the budget held, memory, and how fast a stop request (the flag that the
// daemon's CANCEL and SIGTERM set) ends the search at chosen moments, closure included.

#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <thread>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"
#include "json_output.hpp"
#include "timing.hpp"

namespace ispars::lab {
namespace {

struct StopRun {
  double stop_at = 0.0;
  double returned_at = 0.0;
  bool had_tour = false;
  std::string message;
};

StopRun stop_after(const InspectionGraph& g, double at, std::uint64_t seed) {
  std::atomic<bool> stop{false};
  planning::GipOptions o;
  o.budget_seconds = 3600.0;
  o.seed = seed;
  o.stop = &stop;
  StopRun run;
  run.stop_at = at;
  const double t0 = now_seconds();
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::duration<double>(at));
    stop = true;
  });
  try {
    const planning::GipResult r = planning::solve_gip(g, o);
    run.had_tour = r.validation.valid();
    run.message = fmt::format("tour {:.6g}", r.tour.cost);
  } catch (const std::exception& e) {
    run.message = e.what();
  }
  run.returned_at = now_seconds() - t0;
  stopper.join();
  return run;
}

}  // namespace

int run_bench_tour(const BenchTourOptions& options) {
  const planning::Scene scene = planning::Scene::load(options.scene);
  planning::BuildOptions build;
  build.seed = options.seed;
  build.threads = 2;
  const double b0 = now_seconds();
  const auto builder = planning::make_roadmap_builder(*parse_build_method(options.method), scene, build);
  builder->extend(options.samples);
  const double build_seconds = now_seconds() - b0;
  const InspectionGraph g = InspectionGraph::from_roadmap(builder->roadmap());
  const double rss_graph = peak_rss_mib();
  std::cout << fmt::format(
      "{} roadmap of {} samples on {}: {} vertices, {} edges, built in {:.1f} s; peak RSS {:.0f} MiB\n", options.method,
      options.samples, scene.config().name, g.vertex_count(), g.edge_count(), build_seconds, rss_graph);

  planning::GipOptions o;
  o.budget_seconds = options.budget;
  o.seed = options.seed;
  const double t0 = now_seconds();
  const planning::GipResult r = planning::solve_gip(g, o);
  const double wall = now_seconds() - t0;
  const double rss_tour = peak_rss_mib();
  // The shortcut the daemon gives every tour, with the scene's collision checker.
  const planning::SegmentValid segment_valid = [&scene](const Vec3& a, const Vec3& b) {
    return scene.segment_valid(a, b);
  };
  const double s0 = now_seconds();
  const planning::ShortcutTour shortcut =
      planning::shortcut_tour(g, builder->roadmap().positions(), r.targets, r.tour, segment_valid);
  const double shortcut_seconds = now_seconds() - s0;
  std::cout << fmt::format(
      "budget {:.1f} s: returned after {:.2f} s; first tour at {:.2f} s; best {:.6g} ({}), {} targets, {} candidates "
      "({} thinned), {} distance rows, {} iterations; bound {:.6g}{}; peak RSS {:.0f} MiB\n",
      options.budget, wall, r.trace.empty() ? wall : r.trace.front().first, r.tour.cost,
      r.validation.valid() ? "valid" : "INVALID", r.targets.size(), r.candidates, r.thinned, r.distance_rows,
      r.iterations, r.lower_bound.value_or(0.0), r.bound_note.empty() ? "" : " (" + r.bound_note + ")", rss_tour);
  std::cout << fmt::format("shortcut: {:.6g} from a walk of {} vertices in {:.3f} s ({} segments checked)\n",
                           shortcut.cost, r.tour.walk.size(), shortcut_seconds, shortcut.segments_checked);
  nlohmann::json stops = nlohmann::json::array();
  for (const double at : options.stop_at) {
    const StopRun s = stop_after(g, at, options.seed);
    std::cout << fmt::format("stop requested at {:.2f} s: returned at {:.2f} s ({:.3f} s later), {}\n", s.stop_at,
                             s.returned_at, s.returned_at - s.stop_at, s.message);
    stops.push_back({{"stop_at", s.stop_at},
                     {"returned_at", s.returned_at},
                     {"latency", s.returned_at - s.stop_at},
                     {"had_tour", s.had_tour},
                     {"message", s.message}});
  }
  if (options.json) {
    std::cout << nlohmann::json{{"scene", scene.config().name},
                                {"method", options.method},
                                {"samples", options.samples},
                                {"vertices", g.vertex_count()},
                                {"edges", g.edge_count()},
                                {"build_seconds", build_seconds},
                                {"budget", options.budget},
                                {"returned_after", wall},
                                {"first_tour",
                                 r.trace.empty() ? nlohmann::json() : nlohmann::json(r.trace.front().first)},
                                {"cost", r.tour.cost},
                                {"trace", r.trace},
                                {"valid", r.validation.valid()},
                                {"shortcut_cost", shortcut.cost},
                                {"shortcut_seconds", shortcut_seconds},
                                {"candidates", r.candidates},
                                {"thinned", r.thinned},
                                {"distance_rows", r.distance_rows},
                                {"iterations", r.iterations},
                                {"lower_bound", r.lower_bound.value_or(0.0)},
                                {"bound_note", r.bound_note},
                                {"peak_rss_mib_graph", rss_graph},
                                {"peak_rss_mib", rss_tour},
                                {"stops", stops}}
                     .dump()
              << std::endl;
  }
  return r.validation.valid() ? 0 : 1;
}

CLI::App* add_bench_tour_command(CLI::App& parent, BenchTourOptions& options) {
  auto* cmd =
      parent.add_subcommand("tour", "The tour solver on a large roadmap: first tour, budget, memory, stop latency");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  cmd->add_option("--method", options.method, "dense | spars | ispars | irisc | ispars2")->check(build_method_check());
  cmd->add_option("--samples", options.samples, "N")->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}));
  cmd->add_option("--seed", options.seed, "Seed of the roadmap and the search");
  cmd->add_option("--budget", options.budget, "Seconds of search")->check(CLI::Range(0.01, 3600.0));
  cmd->add_option("--stop-at", options.stop_at, "Request a stop this many seconds after the start")
      ->delimiter(',')
      ->check(CLI::Range(0.0, 3600.0));
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  return cmd;
}

}  // namespace ispars::lab
