#include "tour_support.hpp"

#include <algorithm>
#include <atomic>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "ispars/params/input_error.hpp"

namespace ispars::lab {

std::vector<PoiId> seen_from_root(const InspectionGraph& graph) {
  std::vector<char> seen(graph.poi_count(), 0);
  for (const VertexId v : graph.component_of(0)) {
    for (const PoiId p : graph.visible(v)) seen[p] = 1;
  }
  std::vector<PoiId> out;
  for (PoiId p = 0; p < graph.poi_count(); ++p) {
    if (seen[p]) out.push_back(p);
  }
  return out;
}

std::vector<PoiId> common_targets(std::span<const InspectionGraph* const> graphs) {
  if (graphs.empty()) return {};
  std::vector<PoiId> common = seen_from_root(*graphs.front());
  for (const InspectionGraph* g : graphs.subspan(1)) {
    const std::vector<PoiId> mine = seen_from_root(*g);
    std::vector<PoiId> both;
    std::set_intersection(common.begin(), common.end(), mine.begin(), mine.end(), std::back_inserter(both));
    common = std::move(both);
  }
  return common;
}

InspectionGraph with_viewpoints(const Roadmap& dense, std::span<const VertexId> viewpoints) {
  std::vector<std::vector<PoiId>> visible(dense.vertex_count());
  for (const VertexId v : viewpoints) visible[v] = dense.visibility_table().ids(v);
  const std::vector<RoadmapEdge> edges(dense.edges().begin(), dense.edges().end());
  return InspectionGraph::from_edges(dense.vertex_count(), edges, std::move(visible),
                                     dense.visibility_table().poi_count());
}

std::vector<planning::GipResult> solve_each(std::span<const InspectionGraph* const> graphs,
                                            const std::vector<PoiId>& targets, std::uint64_t seed,
                                            const SolverWork& work) {
  std::vector<planning::GipResult> results(graphs.size());
  run_jobs(graphs.size(), work.jobs, [&](std::size_t i) {
    planning::GipOptions solve;
    solve.targets = targets;
    solve.budget_seconds = work.cap_seconds;
    solve.max_iterations = work.iterations;
    solve.seed = seed;
    solve.lp_bound = false;  // bounds are measured on their own (bound_each), not on the search's time
    planning::GipResult r = planning::solve_gip(*graphs[i], solve);
    if (!r.validation.valid()) throw std::runtime_error("invalid tour: " + r.validation.problem);
    results[i] = std::move(r);
  });
  return results;
}

std::vector<planning::TourBoundResult> bound_each(std::span<const InspectionGraph* const> graphs,
                                                  const std::vector<PoiId>& targets, double seconds, unsigned jobs) {
  std::vector<planning::TourBoundResult> results(graphs.size());
  run_jobs(graphs.size(), jobs, [&](std::size_t i) {
    planning::TourBoundOptions options;
    options.targets = targets;
    options.budget_seconds = seconds;
    results[i] = planning::lp_tour_bound(*graphs[i], options);
  });
  return results;
}

bool hit_time_cap(const planning::GipResult& result, const SolverWork& work) {
  return work.iterations > 0 && result.iterations < work.iterations && result.seconds >= work.cap_seconds;
}

planning::SparsRules parse_rule_set(const std::string& name, const std::string& field) {
  const auto bad = [&](const std::string& why) {
    return params::InputError("experiment", field, "rule set '" + name + "': " + why);
  };
  const std::size_t cut = name.find_first_of("+-");
  const auto variant = parse_spars_variant(name.substr(0, cut));
  if (!variant) throw bad("must start with alg1 or stretch");
  planning::SparsRules rules = planning::SparsRules::for_variant(*variant, true);
  std::size_t at = cut;
  while (at != std::string::npos) {
    const bool on = name[at] == '+';
    const std::size_t end = name.find_first_of("+-", at + 1);
    const std::string rule = name.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1);
    if (rule == "join") {
      rules.vertex_join = on;
    } else if (rule == "witness") {
      rules.witnessed_pairs = on;
    } else if (rule == "bridge") {
      rules.bridge_by_edge = on;
    } else if (rule == "nearest") {
      rules.witness_nearest_only = on;
    } else if (rule == "shortcut") {
      rules.dense_shortcut = on;
    } else {
      throw bad("unknown rule '" + rule + "' (join, witness, shortcut)");
    }
    at = end;
  }
  return rules;
}

}  // namespace ispars::lab
