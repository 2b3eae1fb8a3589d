#include "experiment_support.hpp"

#include <cstdlib>
#include <fstream>

#include <cmath>

#include "timing.hpp"

namespace ispars::lab {

void run_gnuplot(const std::string& png, const std::string& script) {
  const std::string script_path = png + ".gnuplot";
  {
    std::ofstream file(script_path);
    file << script;
  }
  const std::string command = "gnuplot '" + script_path + "' 2>&1";
  const int status = std::system(command.c_str());
  std::remove(script_path.c_str());
  if (status != 0) {
    throw std::runtime_error("gnuplot failed (is gnuplot-nox installed? deploy/install-deps.sh installs it)");
  }
}

MeanSd mean_sd(const std::vector<double>& values) {
  if (values.empty()) return {};
  double sum = 0.0;
  for (const double v : values) sum += v;
  const double mean = sum / static_cast<double>(values.size());
  double squares = 0.0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  const double sd = values.size() > 1 ? std::sqrt(squares / static_cast<double>(values.size() - 1)) : 0.0;
  return {mean, sd};
}

SceneConfig scene_variant(const SceneConfig& base, std::size_t pois, std::uint64_t poi_seed, double delta) {
  SceneConfig c = base;
  if (pois > 0) {
    c.pois.count = pois;
    c.pois.seed = poi_seed;
    c.pois.file.clear();
  }
  if (delta > 0.0) {
    c.dense_delta = delta;
    c.sparse_delta = 1.5 * delta;
  }
  return c;
}

double dense_mean_degree(const Scene& scene, std::size_t samples, unsigned threads) {
  BuildOptions options;
  options.seed = 1;
  options.threads = threads;
  const auto builder = make_roadmap_builder(BuildMethod::dense, scene, options);
  builder->extend(samples);
  const Roadmap& g = builder->roadmap();
  return 2.0 * static_cast<double>(g.edge_count()) / static_cast<double>(g.vertex_count());
}

double calibrate_delta(const SceneConfig& base, std::size_t samples, double target_degree, unsigned threads) {
  // POIs do not change the dense graph: use one, to keep chi(q) cheap.
  const auto degree_at = [&](double delta) {
    return dense_mean_degree(Scene::build(scene_variant(base, 1, 1, delta)), samples, threads);
  };
  // Bracket by steps of 1.25 from the scene's own delta (cheap: evaluations stay near the
  // answer; a much larger delta makes a very dense, slow graph), then bisect geometrically.
  double lo = base.dense_delta;
  double hi = base.dense_delta;
  if (degree_at(lo) < target_degree) {
    do {
      lo = hi;
      hi *= 1.25;
    } while (degree_at(hi) < target_degree);
  } else {
    do {
      hi = lo;
      lo /= 1.25;
    } while (degree_at(lo) > target_degree);
  }
  for (int i = 0; i < 30; ++i) {
    const double mid = std::sqrt(lo * hi);
    const double degree = degree_at(mid);
    if (std::abs(degree - target_degree) <= 0.005 * target_degree) return mid;
    (degree < target_degree ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

RunFigures figures_of(const RoadmapBuilder& builder, const CheckCounts& checks, double seconds) {
  RunFigures f;
  const Roadmap& g = builder.roadmap();
  f.vertices = g.vertex_count();
  f.edges = g.edge_count();
  f.covered = g.covered_pois();
  f.covered_root = g.covered_pois_in_component_of(0);
  if (const Roadmap* d = builder.dense()) {
    f.dense_vertices = d->vertex_count();
    f.dense_edges = d->edge_count();
    f.dense_covered = d->covered_pois();
    f.dense_covered_root = d->covered_pois_in_component_of(0);
  }
  f.checks = checks;
  f.seconds = seconds;
  return f;
}

}  // namespace ispars::lab
