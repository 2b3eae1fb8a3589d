#pragma once
// Shared pieces of the lab's experiments: scene variants, calibration, repeated builds, stats.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/route_stretch.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/scene/scene.hpp"

namespace ispars::lab {

/// Runs gnuplot on `script` (a complete script, including its output file), through a
/// temporary file beside `png`. Throws std::runtime_error when gnuplot fails.
void run_gnuplot(const std::string& png, const std::string& script);

/// Mean and sample standard deviation.
struct MeanSd {
  double mean = 0.0;
  double sd = 0.0;
};
[[nodiscard]] MeanSd mean_sd(const std::vector<double>& values);
/// A table cell "mean +- sd" with `decimals` decimals; "-" for no values.
[[nodiscard]] std::string mean_sd_cell(const std::vector<double>& values, int decimals);

/// The scene's config with K POIs drawn from `poi_seed`, and delta (Delta = 1.5 delta) when
/// `delta` > 0.
[[nodiscard]] scene_files::SceneConfig scene_variant(const scene_files::SceneConfig& base, std::size_t pois,
                                                     std::uint64_t poi_seed, double delta);

/// Mean degree 2|E|/|V| of the dense roadmap after N samples (seed 1).
[[nodiscard]] double dense_mean_degree(const planning::Scene& scene, std::size_t samples, unsigned threads);

/// The delta whose dense roadmap at N samples has the target mean degree (bisection on a
/// monotone curve, to 0.5% in degree), with Delta = 1.5 delta.
[[nodiscard]] double calibrate_delta(const scene_files::SceneConfig& base, std::size_t samples, double target_degree,
                                     unsigned threads);

/// Figures of one finished build.
struct RunFigures {
  std::size_t vertices = 0, edges = 0, covered = 0, covered_root = 0;
  std::size_t dense_vertices = 0, dense_edges = 0, dense_covered = 0, dense_covered_root = 0;
  planning::CheckCounts checks;
  double seconds = 0.0;
};
[[nodiscard]] RunFigures figures_of(const planning::RoadmapBuilder& builder, const planning::CheckCounts& checks,
                                    double seconds);

/// {"admissions": {...}, "edges_by_cause": {...}}.
[[nodiscard]] nlohmann::json to_json(const planning::SparsAdmissions& a);
/// A route-stretch report as JSON: per bin, against the dense route and the straight segment.
[[nodiscard]] nlohmann::json to_json(const planning::RouteStretchReport& r);
/// One line per bin: "[0,1) Delta: 812 pairs, vs dense median 0.97 p95 1.18 max 2.0 (12.1% > t); ...".
[[nodiscard]] std::string stretch_lines(const planning::RouteStretchReport& r);

/// The paper's setting for one of its three scenes: N, K and the dense mean degree of Table II.
struct PaperSetting {
  const char* scene;
  std::size_t samples;
  std::size_t pois;
  double degree;
};
/// water_tower, truss_bridge, caric_city.
[[nodiscard]] const std::vector<PaperSetting>& paper_settings();
/// The setting for `scene`; throws InputError (field "--scene") for any other scene.
[[nodiscard]] const PaperSetting& paper_setting(const std::string& scene);

}  // namespace ispars::lab
