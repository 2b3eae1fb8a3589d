// `ispars-lab bench task`: an inspection task added to a built Inspection-SPARS roadmap (ispars or
// ispars2) against a rebuild from scratch with every POI: seconds, sparse vertices added, and
// tours for the task's POIs on both roadmaps with the same solver work.

#include <fmt/format.h>

#include <algorithm>
#include <iostream>

#include "commands.hpp"
#include "flags.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/scene_files/poi_sampling.hpp"
#include "json_output.hpp"
#include "timing.hpp"
#include "tour_support.hpp"

namespace ispars::lab {
namespace {

struct Timed {
  std::unique_ptr<planning::RoadmapBuilder> builder;
  double seconds = 0.0;
};

Timed build(const planning::Scene& scene, const BenchTaskOptions& options) {
  planning::BuildOptions build;
  build.seed = options.seed;
  build.threads = options.threads;
  const double t0 = now_seconds();
  Timed out{planning::make_roadmap_builder(*parse_build_method(options.method), scene, build), 0.0};
  out.builder->extend(options.samples);
  out.seconds = now_seconds() - t0;
  return out;
}

// The task's POIs (ids from `first` on) seen from the root's component of every graph.
std::vector<PoiId> task_targets(std::span<const InspectionGraph* const> graphs, PoiId first) {
  std::vector<PoiId> targets = common_targets(graphs);
  std::erase_if(targets, [first](PoiId p) { return p < first; });
  return targets;
}

}  // namespace

int run_bench_task(const BenchTaskOptions& options) {
  const planning::Scene scene = planning::Scene::load(options.scene);
  const std::vector<Vec3> task =
      scene_files::sample_pois_on_surface(scene.mesh(), options.pois, options.poi_seed, true);
  const planning::Scene widened = scene.with_more_pois(task);
  const auto first = static_cast<PoiId>(scene.pois().size());

  Timed added = build(scene, options);
  const std::size_t vertices_before = added.builder->roadmap().vertex_count();
  const double a0 = now_seconds();
  const std::size_t guards = added.builder->add_pois(widened);
  const double add_seconds = now_seconds() - a0;
  const Timed rebuilt = build(widened, options);
  std::cout << fmt::format(
      "{}: {}, {} samples, {} POIs + a task of {}\n  built in {:.2f} s ({} sparse vertices); task added in "
      "{:.3f} s (+{} guards)\n  rebuilt with every POI in {:.2f} s ({} sparse vertices): {:.1f}x the addition\n",
      scene.config().name, options.method, options.samples, first, task.size(), added.seconds, vertices_before,
      add_seconds, guards, rebuilt.seconds, rebuilt.builder->roadmap().vertex_count(), rebuilt.seconds / add_seconds);

  const InspectionGraph g_added = InspectionGraph::from_roadmap(added.builder->roadmap());
  const InspectionGraph g_rebuilt = InspectionGraph::from_roadmap(rebuilt.builder->roadmap());
  const std::vector<const InspectionGraph*> graphs{&g_added, &g_rebuilt};
  const std::vector<PoiId> targets = task_targets(graphs, first);
  SolverWork work;
  work.iterations = options.iterations;
  const std::vector<planning::GipResult> tours = solve_each(graphs, targets, options.seed, work);
  const double ratio = tours[0].tour.cost / tours[1].tour.cost;
  std::cout << fmt::format(
      "  tours of the task's {} POIs seen from the root, {} iterations each: added {:.6g}, "
      "rebuilt {:.6g} (added/rebuilt {:.4f})\n",
      targets.size(), options.iterations, tours[0].tour.cost, tours[1].tour.cost, ratio);
  nlohmann::json verified;
  if (options.verify && added.builder->dense() != nullptr) {
    const auto& b = *added.builder;
    const planning::VerificationReport r =
        planning::verify_sparse_pair(widened, b.roadmap(), *b.dense(), b.dense_ids());
    std::cout << fmt::format("  verify (every POI, every dense vertex): {} Invariant 1 violations, geometry {}\n",
                             r.invariant_violations, r.geometry_ok() ? "ok" : "NOT ok");
    verified = {{"invariant_violations", r.invariant_violations}, {"geometry_ok", r.geometry_ok()}};
  }
  if (options.json) {
    std::cout << nlohmann::json{{"scene", scene.config().name},
                                {"method", options.method},
                                {"samples", options.samples},
                                {"scene_pois", first},
                                {"task_pois", task.size()},
                                {"threads", options.threads},
                                {"build_seconds", added.seconds},
                                {"add_seconds", add_seconds},
                                {"sparse_vertices_before", vertices_before},
                                {"guards_added", guards},
                                {"rebuild_seconds", rebuilt.seconds},
                                {"rebuild_sparse_vertices", rebuilt.builder->roadmap().vertex_count()},
                                {"speedup", rebuilt.seconds / add_seconds},
                                {"targets", targets.size()},
                                {"iterations", options.iterations},
                                {"tour_added", tours[0].tour.cost},
                                {"tour_rebuilt", tours[1].tour.cost},
                                {"tour_ratio", ratio},
                                {"verify", verified}}
                     .dump()
              << std::endl;
  }
  return 0;
}

CLI::App* add_bench_task_command(CLI::App& parent, BenchTaskOptions& options) {
  auto* cmd = parent.add_subcommand(
      "task", "An inspection task added to a built ispars roadmap against a rebuild with every POI");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  cmd->add_option("--method", options.method, "ispars | ispars2")->check(CLI::IsMember({"ispars", "ispars2"}));
  cmd->add_option("--samples", options.samples, "N")->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}));
  cmd->add_option("--pois", options.pois, "The task's POIs, sampled on the surface")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000}));
  cmd->add_option("--poi-seed", options.poi_seed, "Seed of the task's POIs");
  cmd->add_option("--seed", options.seed, "Seed of the roadmaps and the tours");
  cmd->add_option("--threads", options.threads, "Threads of each build")->check(CLI::Range(1u, 256u));
  cmd->add_option("--iterations", options.iterations, "Tour solver iterations on each roadmap")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  cmd->add_flag("--verify", options.verify, "Check Invariant 1 over every POI after the addition (ispars)");
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  return cmd;
}

}  // namespace ispars::lab
