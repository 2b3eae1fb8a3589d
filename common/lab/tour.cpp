// `ispars-lab tour`: an inspection tour on a roadmap file or IRIS files.

#include <fmt/format.h>
#include <unistd.h>

#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "ispars/gip_solver.hpp"
#include "ispars/input_error.hpp"
#include "ispars/roadmap_json.hpp"
#include "json_output.hpp"

namespace ispars::lab {

int run_tour(const TourCommandOptions& options) {
  if (options.roadmap.empty() == options.iris.empty()) {
    throw InputError("tour", "input", "give either a roadmap file or --iris PREFIX");
  }
  RoadmapFileGraph input;
  if (!options.iris.empty()) {
    input.graph = InspectionGraph::read_iris(options.iris, options.all_edges);
  } else {
    input = read_roadmap_file_graph(options.roadmap, options.graph);
  }
  GipOptions solve;
  solve.budget_seconds = options.budget;
  solve.seed = options.seed;
  solve.threads = options.threads;
  solve.max_iterations = options.iterations;
  const bool live = !options.json && ::isatty(STDERR_FILENO);
  if (live) {
    solve.on_improvement = [](double t, double cost) {
      std::cerr << fmt::format("\r{:8.2f} s  best tour {:.6g}   ", t, cost) << std::flush;
    };
  }
  const GipResult r = solve_gip(input.graph, solve);
  if (live) std::cerr << '\n';

  nlohmann::json trace = nlohmann::json::array();
  for (const auto& [t, c] : r.trace) trace.push_back({t, c});
  const nlohmann::json lower = r.lower_bound ? nlohmann::json(*r.lower_bound) : nlohmann::json();
  const nlohmann::json out = {{"cost", r.tour.cost},
                              {"covered", r.tour.covered.size()},
                              {"targets", r.targets.size()},
                              {"seconds", r.seconds},
                              {"lower_bound", lower},
                              {"valid", r.validation.valid()},
                              {"trace", trace},
                              {"walk_steps", r.tour.walk.size() - 1},
                              {"candidates", r.candidates},
                              {"iterations", r.iterations},
                              {"vertices", input.graph.vertex_count()},
                              {"edges", input.graph.edge_count()}};
  if (!options.out.empty()) {
    nlohmann::json file = {{"cost", r.tour.cost}, {"walk", r.tour.walk}, {"covered", r.tour.covered},
                           {"targets", r.targets}, {"valid", r.validation.valid()}, {"trace", trace}};
    if (!input.positions.empty()) {
      nlohmann::json positions = nlohmann::json::array();
      for (const VertexId v : r.tour.walk) positions.push_back(to_json(input.positions[v]));
      file["positions"] = std::move(positions);
    }
    std::ofstream f(options.out);
    if (!f) throw InputError(options.out, "--out", "cannot open for writing");
    f << file.dump() << '\n';
    if (!f) throw InputError(options.out, "--out", "write failed");
  }
  if (options.json) {
    std::cout << out.dump() << std::endl;
  } else {
    std::cout << fmt::format("graph: {} vertices, {} edges; {} targets, {} candidate vertices\n",
                             input.graph.vertex_count(), input.graph.edge_count(), r.targets.size(), r.candidates);
    std::cout << fmt::format("tour: cost {:.6g}, {} steps, covers {}/{} targets, {}\n", r.tour.cost,
                             r.tour.walk.size() - 1, r.tour.covered.size(), r.targets.size(),
                             r.validation.valid() ? "valid" : "INVALID: " + r.validation.problem);
    if (r.lower_bound) {
      std::cout << fmt::format("lower bound {:.6g} (gap {:.1f}%)\n", *r.lower_bound,
                               100.0 * (r.tour.cost - *r.lower_bound) / r.tour.cost);
    }
    std::cout << fmt::format("{} improvements in {:.2f} s, {} search iterations\n", r.trace.size(), r.seconds,
                             r.iterations);
  }
  return r.validation.valid() ? 0 : 1;
}

}  // namespace ispars::lab
