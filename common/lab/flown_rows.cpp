#include "flown_rows.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>

namespace ispars::lab {
namespace {

// What a row tours: a graph, its vertices' positions, and the pipeline's stages it runs.
struct RowInput {
  const char* name;
  InspectionGraph graph;
  std::span<const Vec3> positions;
  bool corridor = false;
  bool refine = false;
  planning::CorridorSource source = planning::CorridorSource::fresh;
  std::span<const Vec3> samples = {};  // with CorridorSource::samples
};

planning::FlownTourOptions row_options(const RowInput& in, const std::vector<PoiId>& targets, const SolverWork& work,
                                       std::uint64_t seed, std::size_t samples) {
  planning::FlownTourOptions o;
  o.search.targets = targets;
  o.search.max_iterations = work.iterations;
  o.search.budget_seconds = work.cap_seconds;
  o.search.seed = seed;
  o.search.lp_bound = false;
  o.build_samples = samples;
  o.rounds = in.corridor ? o.rounds : 0;
  o.corridor_source = in.source;
  o.corridor_samples = in.samples;
  o.build_seed = seed;  // build_seed_roadmaps builds with the row's seed
  o.refine = in.refine;
  return o;
}

FlownRow run_row(const SeedRoadmaps& roadmaps, const RowInput& in, const std::vector<PoiId>& common,
                 const SolverWork& work, std::uint64_t seed) {
  FlownRow row;
  row.name = in.name;
  row.vertices = in.graph.vertex_count();
  std::vector<PoiId> targets;  // the common targets this roadmap reaches (random@|V| may lose some)
  const std::vector<PoiId> reached = seen_from_root(in.graph);
  std::set_intersection(common.begin(), common.end(), reached.begin(), reached.end(), std::back_inserter(targets));
  row.targets = targets.size();
  row.targets_lost = common.size() - targets.size();
  const auto start = std::chrono::steady_clock::now();
  row.tour = planning::fly_tour(roadmaps.scene, in.graph, in.positions,
                                row_options(in, targets, work, seed, roadmaps.samples));
  row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!row.tour.check.valid()) {
    throw std::runtime_error(fmt::format("{}: the flown tour failed its check: {}", in.name, row.tour.check.problem));
  }
  return row;
}

std::vector<RowInput> row_inputs(const SeedRoadmaps& r) {
  const Roadmap& ispars = r.ispars->roadmap();
  const Roadmap& wide = r.wide->roadmap();
  const Roadmap& random = r.random->roadmap();
  std::vector<RowInput> rows;
  rows.push_back({"ispars", InspectionGraph::from_roadmap(ispars), ispars.positions()});
  rows.push_back({"ispars-flown", InspectionGraph::from_roadmap(ispars), ispars.positions(), true, true});
  rows.push_back({"dense-wide", InspectionGraph::from_roadmap(wide), wide.positions()});
  rows.push_back({"dense-wide-refined", InspectionGraph::from_roadmap(wide), wide.positions(), false, true});
  // The same stream: Dense-wide's vertex i is the dense pair's vertex i (dense_ids index both).
  rows.push_back({"dense-wide/ispars-viewpoints", with_viewpoints(wide, r.ispars->dense_ids()), wide.positions()});
  rows.push_back({"random@|V|", InspectionGraph::from_roadmap(random), random.positions()});
  // The corridor from the build's own samples: the dense pair's vertices (ispars), or the seed's
  // stream drawn again (ispars2, whose sparse roadmap is ispars's byte for byte).
  rows.push_back({"ispars-flown/dense-samples", InspectionGraph::from_roadmap(ispars), ispars.positions(), true, true,
                  planning::CorridorSource::samples, r.ispars->dense()->positions()});
  rows.push_back({"ispars-flown/stream", InspectionGraph::from_roadmap(ispars), ispars.positions(), true, true,
                  planning::CorridorSource::stream});
  return rows;
}

}  // namespace

SeedRoadmaps build_seed_roadmaps(const scene_files::SceneConfig& base, const PaperSetting& ps, std::uint64_t seed,
                                 double delta, unsigned threads) {
  SeedRoadmaps r{planning::Scene::build(scene_variant(base, ps.pois, seed, delta)),
                 planning::Scene::build(scene_variant(base, ps.pois, seed, 3.0 * delta)),
                 nullptr,
                 nullptr,
                 nullptr,
                 ps.samples};
  planning::BuildOptions build;
  build.seed = seed;
  build.threads = threads;
  r.ispars = std::make_unique<planning::SparsBuilder>(r.scene, build,
                                                      planning::SparsRules::for_variant(SparsVariant::stretch, true));
  r.ispars->extend(ps.samples);
  r.wide = std::make_unique<planning::DenseBuilder>(r.wide_scene, build);
  r.wide->extend(ps.samples);
  r.random = std::make_unique<planning::DenseBuilder>(r.wide_scene, build);
  const std::size_t wanted = r.ispars->roadmap().vertex_count();
  while (r.random->roadmap().vertex_count() < wanted) r.random->extend(1);
  return r;
}

const std::vector<std::string>& flown_row_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const char* name :
         {"ispars", "ispars-flown", "dense-wide", "dense-wide-refined", "dense-wide/ispars-viewpoints", "random@|V|",
          "ispars-flown/dense-samples", "ispars-flown/stream"}) {
      out.emplace_back(name);
    }
    return out;
  }();
  return names;
}

std::vector<FlownRow> flown_rows(const SeedRoadmaps& roadmaps, const SolverWork& work, std::uint64_t seed,
                                 std::span<const std::string> only) {
  std::vector<RowInput> inputs = row_inputs(roadmaps);
  // I_t: the POIs seen from the root's component of ispars, Dense-wide and its viewpoint-restricted
  // graph (random@|V| tours what it reaches of them, and counts the rest as lost).
  const std::vector<const InspectionGraph*> graphs{&inputs[0].graph, &inputs[2].graph, &inputs[4].graph};
  const std::vector<PoiId> common = common_targets(graphs);
  if (!only.empty()) {
    std::erase_if(inputs,
                  [&](const RowInput& in) { return std::find(only.begin(), only.end(), in.name) == only.end(); });
  }
  std::vector<FlownRow> rows(inputs.size());
  run_jobs(inputs.size(), work.jobs,
           [&](std::size_t i) { rows[i] = run_row(roadmaps, inputs[i], common, work, seed); });
  return rows;
}

std::pair<double, double> equal_time(const SeedRoadmaps& roadmaps, double budget, std::uint64_t seed) {
  const std::vector<RowInput> inputs = row_inputs(roadmaps);
  const std::vector<const InspectionGraph*> graphs{&inputs[0].graph, &inputs[2].graph, &inputs[4].graph};
  const std::vector<PoiId> common = common_targets(graphs);
  double cost[2] = {std::nan(""), std::nan("")};
  const std::size_t which[2] = {kFlownRow, kDenseWideRow};
  run_jobs(2, 2, [&](std::size_t k) {
    const RowInput& in = inputs[which[k]];
    planning::FlownTourOptions o = row_options(in, common, SolverWork{0, budget, 1}, seed, roadmaps.samples);
    try {
      cost[k] = planning::fly_tour(roadmaps.scene, in.graph, in.positions, o).cost;
    } catch (const std::runtime_error&) {
      // no tour within the budget: NaN
    }
  });
  return {cost[0], cost[1]};
}

std::string ratio_interval_cell(const std::vector<double>& ratios) {
  if (ratios.empty()) return "-";
  // Student's t at 97.5% for n - 1 degrees of freedom (n = 2 .. 21).
  static const double t975[] = {0.0,   0.0,   12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262,
                                2.228, 2.201, 2.179,  2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086};
  const MeanSd ms = mean_sd(ratios);
  const double t = ratios.size() < std::size(t975) ? t975[ratios.size()] : 2.0;
  const double half = ratios.size() > 1 ? t * ms.sd / std::sqrt(static_cast<double>(ratios.size())) : 0.0;
  return fmt::format("{:.3f} [{:.3f}, {:.3f}], worst {:.3f}", ms.mean, ms.mean - half, ms.mean + half,
                     *std::max_element(ratios.begin(), ratios.end()));
}

std::string equal_time_row(const std::string& scene, double budget, const std::vector<double>& flown,
                           const std::vector<double>& wide) {
  std::vector<double> ratios, f, w;
  for (std::size_t i = 0; i < flown.size(); ++i) {
    if (!std::isnan(flown[i])) f.push_back(flown[i]);
    if (!std::isnan(wide[i])) w.push_back(wide[i]);
    if (!std::isnan(flown[i]) && !std::isnan(wide[i])) ratios.push_back(flown[i] / wide[i]);
  }
  const auto cell = [](const std::vector<double>& v, std::size_t of) {
    return v.empty() ? std::string("-") : fmt::format("{} ({}/{} seeds)", mean_sd_cell(v, 2), v.size(), of);
  };
  return fmt::format("| {} | {:g} | {} | {} | {} |\n", scene, budget, cell(f, flown.size()), cell(w, wide.size()),
                     ratio_interval_cell(ratios));
}

nlohmann::json row_json(const std::string& scene, std::uint64_t seed, const FlownRow& row) {
  nlohmann::json stages = nlohmann::json::array();
  for (const planning::FlownStage& s : row.tour.stages)
    stages.push_back({{"stage", s.name}, {"cost", s.cost}, {"seconds", s.seconds}});
  return {{"scene", scene},
          {"seed", seed},
          {"row", row.name},
          {"vertices", row.vertices},
          {"edges", row.tour.graph_edges},
          {"graph_vertices", row.tour.graph_vertices},
          {"targets", row.targets},
          {"targets_lost", row.targets_lost},
          {"walk_cost", row.tour.walk_cost},
          {"shortcut_cost", row.tour.cost},
          {"stops", row.tour.stops.size()},
          {"corridor_samples", row.tour.corridor_samples},
          {"segments_checked", row.tour.segments_checked},
          {"refine_moved", row.tour.refined.moved},
          {"refine_dropped", row.tour.refined.dropped},
          {"refine_reversed", row.tour.refined.reversed},
          {"iterations", row.tour.search.iterations},
          {"seconds", row.seconds},
          {"check", row.tour.check.valid()},
          {"stages", stages}};
}

}  // namespace ispars::lab
