#pragma once
// The rows of the flown-tour experiment for one scene and seed: the roadmaps (Inspection-SPARS
// and Dense-wide on the same sample stream, and a random roadmap as large as Inspection-SPARS),
// and each row's tour through the flown-tour pipeline (flown_tour.hpp) with the same solver work.

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "experiment_support.hpp"
#include "ispars/planning/builders/dense_builder.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/tour/flown_tour.hpp"
#include "tour_support.hpp"

namespace ispars::lab {

/// The roadmaps of one seed, calibrated as Table II.
struct SeedRoadmaps {
  planning::Scene scene;       ///< delta calibrated, Delta = 1.5 delta: Inspection-SPARS's
  planning::Scene wide_scene;  ///< the same with delta = 2 Delta: Dense-wide's (the same geometry and POIs)
  std::unique_ptr<planning::SparsBuilder> ispars;  ///< the default rules
  std::unique_ptr<planning::DenseBuilder> wide;    ///< the same stream joined within 2 Delta
  std::unique_ptr<planning::DenseBuilder> random;  ///< the stream's first samples joined within 2 Delta, |V| = ispars's
  std::size_t samples = 0;                         ///< N
};

/// Builds the roadmaps of `seed` for the paper's setting `ps` with the calibrated `delta`.
[[nodiscard]] SeedRoadmaps build_seed_roadmaps(const scene_files::SceneConfig& base, const PaperSetting& ps,
                                               std::uint64_t seed, double delta, unsigned threads);

/// One row: a roadmap's tour through the pipeline.
struct FlownRow {
  std::string name;
  std::size_t vertices = 0;      ///< Of the roadmap.
  std::size_t targets = 0;       ///< Targets toured.
  std::size_t targets_lost = 0;  ///< Of the common targets, those this roadmap does not reach.
  planning::FlownTour tour;
  double seconds = 0.0;  ///< The pipeline's wall time.
};

/// Row indices in flown_row_names().
inline constexpr std::size_t kFlownRow = 1, kDenseWideRow = 2;

/// The rows' names, in their order: ispars (the roadmap walk, shortcut), ispars-flown (the
/// daemon's pipeline), dense-wide (walk, shortcut), dense-wide-refined (and viewpoint refinement),
/// dense-wide/ispars-viewpoints (Dense-wide's graph, chi only on ispars's vertices), random@|V|,
/// and ispars-flown with its corridor from the dense pair's vertices (/dense-samples) or the
/// seed's stream drawn again (/stream).
[[nodiscard]] const std::vector<std::string>& flown_row_names();

/// The rows named in `only` (every row when empty), in flown_row_names()'s order.
[[nodiscard]] std::vector<FlownRow> flown_rows(const SeedRoadmaps& roadmaps, const SolverWork& work, std::uint64_t seed,
                                               std::span<const std::string> only = {});

/// The best flown tour of ispars-flown and of Dense-wide (shortcut) within `budget` seconds of
/// wall clock on one thread each (NaN where no tour came by then).
[[nodiscard]] std::pair<double, double> equal_time(const SeedRoadmaps& roadmaps, double budget, std::uint64_t seed);

/// "mean [low, high], worst x" of paired ratios: the mean with its 95% interval (Student's t).
[[nodiscard]] std::string ratio_interval_cell(const std::vector<double>& ratios);

/// "| scene | budget | flown mean | wide mean | ratio cell |" over the seeds.
[[nodiscard]] std::string equal_time_row(const std::string& scene, double budget, const std::vector<double>& flown,
                                         const std::vector<double>& wide);

/// One row as JSON: its figures and its stages.
[[nodiscard]] nlohmann::json row_json(const std::string& scene, std::uint64_t seed, const FlownRow& row);

}  // namespace ispars::lab
