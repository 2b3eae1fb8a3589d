// `ispars-lab experiment spanner`: route quality of the sparse roadmap, per rule set.
// - Between sparse viewpoints (what Theorem 1 would need): for every pair of POI-seeing sparse
//   vertices, far ones included, the sparse route against the dense route and against the
//   straight segment where valid, binned by distance up to 10 Delta (route_stretch.hpp; exact:
//   one Dijkstra per viewpoint on each graph).
// - SPARS's own bound on random dense pairs: d_s <= t d_d + 4 Delta, with the representatives.
// With admissions and edges by cause, and Invariant 1 checked exactly.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/search/graph_search.hpp"
#include "timing.hpp"
#include "tour_support.hpp"

namespace ispars::lab {
namespace {

struct RandomPairs {
  std::size_t measured = 0, disconnected = 0, within_bound = 0;
  double median = 0.0, p95 = 0.0;
};

// SPARS's general bound on random pairs of dense vertices in the root's component.
RandomPairs random_pairs(const planning::SparsBuilder& b, std::size_t pairs, std::uint64_t seed) {
  const Roadmap& dense = *b.dense();
  const Roadmap& sparse = b.roadmap();
  std::vector<VertexId> rooted;
  for (VertexId v = 0; v < dense.vertex_count(); ++v) {
    if (dense.same_component(v, 0)) rooted.push_back(v);
  }
  RandomPairs r;
  if (rooted.size() < 2) return r;
  scene_files::Rng rng(seed);
  std::vector<double> ratios;
  for (std::size_t i = 0; i < pairs; ++i) {
    const VertexId a = rooted[rng.below(rooted.size())];
    VertexId c = a;
    while (c == a) c = rooted[rng.below(rooted.size())];
    const double dd = planning::shortest_distances(dense, a)[c];
    const VertexId ra = b.representative(a);
    const VertexId rc = b.representative(c);
    const double ds = ra == kNoVertex || rc == kNoVertex ? INFINITY
                                                         : (dense.position(a) - sparse.position(ra)).norm() +
                                                               planning::shortest_distances(sparse, ra)[rc] +
                                                               (sparse.position(rc) - dense.position(c)).norm();
    if (!std::isfinite(ds)) {
      ++r.disconnected;
      continue;
    }
    ratios.push_back(ds / dd);
  }
  std::sort(ratios.begin(), ratios.end());
  r.measured = ratios.size();
  if (!ratios.empty()) {
    r.median = ratios[(ratios.size() - 1) / 2];
    r.p95 = ratios[std::min(ratios.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(ratios.size())))];
  }
  return r;
}

// A rule set by name: "spars" is SPARS itself (Alg. 1 without its inspection test); anything
// else as `experiment ablation` reads it (stretch, alg1, stretch+shortcut, ...), with the
// inspection test.
planning::SparsRules spanner_rules(const std::string& name) {
  if (name == "spars") return planning::SparsRules::for_variant(SparsVariant::alg1, false);
  return parse_rule_set(name, "--variants");
}

}  // namespace

int run_experiment_spanner(const ExperimentOptions& options) {
  const scene_files::SceneConfig base =
      scene_files::parse_scene_config(options.scenes_dir + "/" + options.scene + ".yaml");
  std::size_t samples = options.samples;
  std::size_t pois = options.pois;
  double delta = options.delta;
  if (options.calibrate) {
    const PaperSetting& paper = paper_setting(options.scene);
    if (samples == 0) samples = paper.samples;
    if (pois == 0) pois = paper.pois;
    if (delta == 0.0) delta = calibrate_delta(base, samples, paper.degree, options.threads);
  }
  if (samples == 0)
    throw params::InputError("experiment spanner", "--samples", "give N, or --calibrate for the paper's N");
  const planning::Scene scene = planning::Scene::build(scene_variant(base, pois, options.build_seed, delta));
  const double t = scene.config().stretch;
  const double big_delta = scene.config().sparse_delta;
  std::cout << fmt::format("# Route quality on {} (N = {}, K = {}, delta {:.3f}, Delta {:.3f}, t {}, seed {})\n",
                           options.scene, samples, scene.pois().size(), scene.config().dense_delta, big_delta, t,
                           options.build_seed);

  nlohmann::json results = nlohmann::json::array();
  for (const std::string& name : options.variants) {
    const planning::SparsRules rules = spanner_rules(name);
    planning::BuildOptions build;
    build.seed = options.build_seed;
    build.threads = options.threads;
    const double t0 = now_seconds();
    planning::SparsBuilder builder(scene, build, rules);
    builder.extend(samples);
    const double seconds = now_seconds() - t0;
    const Roadmap& sparse = builder.roadmap();
    const Roadmap& dense = *builder.dense();
    planning::RouteStretchOptions ro;
    ro.big_delta = big_delta;
    ro.stretch = t;
    ro.max_sources = options.max_sources;
    const planning::RouteStretchReport stretch =
        planning::measure_route_stretch(scene, sparse, dense, builder.dense_ids(), ro);
    const RandomPairs rp = random_pairs(builder, options.pairs, options.seeds);
    const planning::VerificationReport verified =
        planning::verify_sparse_pair(scene, sparse, dense, builder.dense_ids());

    nlohmann::json r = to_json(builder.admissions());
    r["variant"] = name;
    r["seconds"] = seconds;
    r["vertices"] = sparse.vertex_count();
    r["edges"] = sparse.edge_count();
    r["components"] = sparse.component_count();
    r["dense_vertices"] = dense.vertex_count();
    r["dense_edges"] = dense.edge_count();
    r["invariant_violations"] = verified.invariant_violations;
    r["geometry_ok"] = verified.geometry_ok();
    r["viewpoint_stretch"] = to_json(stretch);
    r["random_pairs"] = {{"pairs", options.pairs},
                         {"measured", rp.measured},
                         {"disconnected", rp.disconnected},
                         {"median_ratio", rp.median},
                         {"p95_ratio", rp.p95}};
    results.push_back(r);

    std::cout << fmt::format(
        "\n## {}: {} vertices, {} edges, {} components (dense {} / {}), built in {:.2f} s; Invariant 1 violations {}\n",
        name, sparse.vertex_count(), sparse.edge_count(), sparse.component_count(), dense.vertex_count(),
        dense.edge_count(), seconds, verified.invariant_violations);
    std::cout << "admissions and edges by cause: " << to_json(builder.admissions()).dump() << '\n';
    std::cout << fmt::format("sparse viewpoints: {} (pairs from {} of them)\n", stretch.viewpoints, stretch.sources)
              << stretch_lines(stretch);
    std::cout << fmt::format(
        "random dense pairs (SPARS's bound, through the representatives): {} pairs, d_s/d_d median {:.3f}, p95 {:.3f}; "
        "{} with ends in different sparse components\n",
        rp.measured, rp.median, rp.p95, rp.disconnected);
  }
  if (options.json) {
    std::cout << nlohmann::json{{"scene", options.scene},      {"samples", samples},
                                {"pois", scene.pois().size()}, {"delta", scene.config().dense_delta},
                                {"Delta", big_delta},          {"t", t},
                                {"seed", options.build_seed},  {"spanner", results}}
                     .dump()
              << std::endl;
  }
  return 0;
}

CLI::App* add_experiment_spanner_command(CLI::App& parent, ExperimentOptions& options) {
  options.seeds = 1;  // --pairs-seed
  auto* cmd = parent.add_subcommand(
      "spanner", "Route quality: sparse viewpoint pairs against dense routes and segments, by distance, per variant");
  add_experiment_flags(*cmd, options);
  cmd->add_option("--scene", options.scene, "Scene name in --scenes");
  cmd->add_flag("--calibrate", options.calibrate,
                "The paper's N, K and calibrated delta for the scene (water_tower, truss_bridge, caric_city)");
  cmd->add_option("--samples", options.samples, "N")->check(CLI::Range(1, 100'000'000));
  cmd->add_option("--pairs", options.pairs, "Random pairs of dense vertices (SPARS's bound)")
      ->check(CLI::Range(1, 10'000'000));
  cmd->add_option("--pois", options.pois, "K")->check(CLI::Range(1, 10'000'000));
  cmd->add_option("--delta", options.delta, "delta (0: the scene's, or calibrated)")->check(CLI::Range(0.0, 1e6));
  cmd->add_option("--seed", options.build_seed, "Seed of the build (and of the POIs)");
  cmd->add_option("--pairs-seed", options.seeds, "Seed of the random dense pairs");
  cmd->add_option("--max-sources", options.max_sources, "Measure pairs from at most this many viewpoints (0: all)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{100'000'000}));
  cmd->add_option("--variants", options.variants,
                  "Rule sets to compare: " + ispars::spars_variant_names() +
                      ", spars (SPARS: alg1 without the inspection test), or a rule set as "
                      "--rule-sets of ablation reads it (e.g. stretch+shortcut)")
      ->delimiter(',');
  return cmd;
}

}  // namespace ispars::lab
