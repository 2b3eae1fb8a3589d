// `ispars-lab experiment spanner`: the path quality SPARS promises. For random pairs of dense
// vertices in the root's component: the shortest route through the sparse roadmap (joined to
// each end's representative) against the shortest dense path.

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "ispars/graph_search.hpp"
#include "ispars/spars_builder.hpp"

namespace ispars::lab {

int run_experiment_spanner(const ExperimentOptions& options) {
  const SceneConfig base = parse_scene_config(options.scenes_dir + "/" + options.scene + ".yaml");
  const double delta = options.delta > 0.0 ? options.delta : base.dense_delta;
  const Scene scene = Scene::build(scene_variant(base, options.pois, 1, delta));
  const double t = scene.config().stretch;
  const double big_delta = scene.config().sparse_delta;

  nlohmann::json results = nlohmann::json::array();
  for (const bool inspection : {false, true}) {
    BuildOptions build;
    build.seed = 1;
    build.threads = options.threads;
    SparsBuilder builder(scene, build, inspection);
    builder.extend(options.samples);
    const Roadmap& dense = *builder.dense();
    const Roadmap& sparse = builder.roadmap();

    std::vector<VertexId> rooted;
    for (VertexId v = 0; v < dense.vertex_count(); ++v) {
      if (dense.same_component(v, 0)) rooted.push_back(v);
    }
    Rng rng(options.seeds);
    std::vector<double> ratios;
    std::size_t within_bound = 0;
    std::size_t disconnected = 0;
    for (std::size_t i = 0; i < options.pairs && rooted.size() > 1; ++i) {
      const VertexId a = rooted[rng.below(rooted.size())];
      VertexId b = a;
      while (b == a) b = rooted[rng.below(rooted.size())];
      const double dd = shortest_distances(dense, a)[b];
      const VertexId ra = builder.representative(a);
      const VertexId rb = builder.representative(b);
      const double through = shortest_distances(sparse, ra)[rb];
      const double ds = (dense.position(a) - sparse.position(ra)).norm() + through +
                        (sparse.position(rb) - dense.position(b)).norm();
      if (!std::isfinite(ds)) {
        ++disconnected;
        continue;
      }
      ratios.push_back(ds / dd);
      within_bound += ds <= t * dd + 4.0 * big_delta;
    }
    std::sort(ratios.begin(), ratios.end());
    const auto quantile = [&](double q) {
      return ratios.empty() ? 0.0 : ratios[std::min(ratios.size() - 1, static_cast<std::size_t>(q * static_cast<double>(ratios.size())))];
    };
    const std::size_t measured = ratios.size();
    const nlohmann::json r = {{"method", inspection ? "ispars" : "spars"},
                              {"pairs", options.pairs},
                              {"connected_pairs", measured},
                              {"disconnected_pairs", disconnected},
                              {"median_ratio", quantile(0.5)},
                              {"p95_ratio", quantile(0.95)},
                              {"max_ratio", ratios.empty() ? 0.0 : ratios.back()},
                              {"share_within_t_dd_plus_4Delta",
                               options.pairs ? static_cast<double>(within_bound) / static_cast<double>(options.pairs) : 0.0},
                              {"sparse_vertices", sparse.vertex_count()},
                              {"dense_vertices", dense.vertex_count()}};
    results.push_back(r);
    std::cout << fmt::format(
        "{:<7} on {} (N = {}, delta {:.3f}, Delta {:.3f}, t {}): {} pairs, d_s/d_d median {:.3f}, p95 {:.3f}, max "
        "{:.3f}; d_s <= t d_d + 4 Delta for {:.1f}% of pairs; {} pairs with ends in different sparse components\n",
        r["method"].get<std::string>(), options.scene, options.samples, delta, big_delta, t, options.pairs,
        quantile(0.5), quantile(0.95), r["max_ratio"].get<double>(),
        100.0 * r["share_within_t_dd_plus_4Delta"].get<double>(), disconnected);
  }
  if (options.json) std::cout << nlohmann::json{{"spanner", results}}.dump() << std::endl;
  return 0;
}

}  // namespace ispars::lab
