#pragma once
// The lab's subcommands. Each prints a human report, or with `json` one JSON object as the last
// line of stdout; bad input surfaces as params::InputError for main() to report.

#include <cstdint>
#include <string>
#include <vector>

#include "ispars/roadmap/build_request.hpp"

namespace CLI {
class App;
}  // namespace CLI

namespace ispars::lab {

// Each subcommand: its options, add_*_command (declares it under `parent`, parsing into
// `options`) and run_* (does it), both in the subcommand's own file.

struct SceneInfoOptions {
  std::string scene;
  bool json = false;
  std::size_t samples = 10'000;  ///< Random valid configurations for the coverage estimate.
  std::uint64_t seed = 1;
};
CLI::App* add_scene_info_command(CLI::App& parent, SceneInfoOptions& options);
int run_scene_info(const SceneInfoOptions& options);

struct BenchGeometryOptions {
  std::string scene;
  bool json = false;
  std::size_t queries = 20'000;         ///< Queries per fast-path measurement.
  std::size_t reference_queries = 200;  ///< Queries through the brute-force reference.
  std::uint64_t seed = 1;
};
CLI::App* add_bench_geometry_command(CLI::App& parent, BenchGeometryOptions& options);
int run_bench_geometry(const BenchGeometryOptions& options);

struct BuildCommandOptions {
  std::string scene;
  std::string method;
  std::string variant;                    ///< spars, ispars: the rule set (empty: stretch)
  BuildRequest request{.samples = 1000};  ///< samples, seed and overrides (method and variant set from the names)
  unsigned threads = 1;
  bool verify = false;
  std::size_t fresh = 0;  ///< fresh samples to check Invariant 1 on (0: none)
  bool json = false;
  std::string out;   ///< --out FILE.json: the roadmap (and its dense pair) in full.
  std::string iris;  ///< --iris PREFIX: IRIS text files PREFIX_vertex, _edge, _conf.
};
CLI::App* add_build_command(CLI::App& parent, BuildCommandOptions& options);
int run_build(const BuildCommandOptions& options);

struct BenchBuildOptions {
  std::string scene;
  std::string method = "ispars";
  std::string variant;                      ///< spars, ispars: the rule set (empty: stretch)
  BuildRequest request{.samples = 20'000};  ///< samples, seed and overrides
  std::size_t checkpoints = 10;
  unsigned threads = 1;
  bool json = false;
};
CLI::App* add_bench_build_command(CLI::App& parent, BenchBuildOptions& options);
int run_bench_build(const BenchBuildOptions& options);

struct BenchTaskOptions {
  std::string scene;
  std::string method = "ispars";  ///< ispars or ispars2
  std::size_t samples = 100'000;
  std::size_t pois = 500;  ///< The task's POIs, sampled on the surface.
  std::uint64_t poi_seed = 7;
  std::uint64_t seed = 1;
  unsigned threads = 2;
  std::uint64_t iterations = 20'000;  ///< Tour solver iterations on each roadmap.
  bool verify = false;
  bool json = false;
};
CLI::App* add_bench_task_command(CLI::App& parent, BenchTaskOptions& options);
int run_bench_task(const BenchTaskOptions& options);

struct BenchTourOptions {
  std::string scene;
  std::string method = "dense";
  std::size_t samples = 100'000;
  std::uint64_t seed = 1;
  double budget = 2.0;
  std::vector<double> stop_at{0.2, 2.0};  ///< Seconds after the start at which to request a stop.
  bool json = false;
};
CLI::App* add_bench_tour_command(CLI::App& parent, BenchTourOptions& options);
int run_bench_tour(const BenchTourOptions& options);

struct ExperimentOptions {
  std::string scenes_dir = ISPARS_DEFAULT_SCENES_DIR;
  std::uint64_t seeds = 6;
  unsigned threads = 2;
  bool json = false;
  // scaling
  std::string scene = "water_tower";
  std::size_t max_samples = 20'000;
  std::size_t pois = 0;  ///< K; 0: 100 for scaling, the paper's K (or the scene's) for spanner
  double delta = 0.0;    ///< 0: calibrate to the paper's density (water tower: degree 7.36 at N = 4000)
  std::string csv;
  std::string png;
  // spanner
  std::size_t samples = 0;  ///< 0: the paper's N (with --calibrate)
  std::size_t pairs = 1000;
  bool calibrate = false;  ///< delta, N and K of the paper's setting for the scene
  std::uint64_t build_seed = 1;
  std::size_t max_sources = 0;  ///< 0: every sparse viewpoint
  std::vector<std::string> variants{"stretch", "alg1"};
  // anytime, ablation
  double budget = 30.0;  ///< anytime without --iterations: seconds per roadmap
  double cap = 600.0;    ///< with --iterations: the wall-clock safety cap per tour
  unsigned jobs = 2;
  std::uint64_t iterations = 30'000;      ///< solver iterations per roadmap (0: the budget alone)
  bool replot = false;                    ///< anytime: only draw --png from an existing --csv
  double bound_seconds = 20.0;            ///< anytime: seconds of LP bound per roadmap (0: none)
  double stretch_slack = 0.0;             ///< ablation: the stretch rules' slack (a fraction of Delta)
  std::uint64_t stretch_slack_after = 0;  ///< ablation: the slack applies from this sample on
  bool wide = false;                      ///< ablation: tour Dense-wide too
  // flown
  std::vector<std::string> only_scenes;         ///< The scenes to run (default: the paper's three).
  std::vector<double> budgets{0.1, 1.0, 10.0};  ///< The equal-time panel's wall-clock budgets.
  std::vector<std::string> rows;                ///< The rows to run (default: every one).
  /// An earlier run's --json output: Dense-wide's flown tours per scene and seed, when the
  /// dense-wide row is not run (equal work makes them deterministic; its iterations must match).
  std::string wide_from;
  std::vector<std::string> rule_sets{"alg1",          "alg1+join",        "alg1+witness",
                                     "alg1-shortcut", "stretch+shortcut", "stretch"};
};
struct TourCommandOptions {
  std::string roadmap;  ///< A roadmap file (ispars-lab build --out / ispars snapshot --out).
  std::string graph = "roadmap";
  std::string iris;        ///< Or IRIS files PREFIX_vertex, PREFIX_edge.
  bool all_edges = false;  ///< IRIS: keep edges marked invalid too.
  double budget = 10.0;
  std::uint64_t seed = 1;
  unsigned threads = 1;
  std::uint64_t iterations = 0;
  std::string targets;              ///< A file of POI ids (default: every POI seen from the root's component).
  std::string bound = "lp";         ///< "lp" or "simple".
  std::string scene;                ///< The roadmap's scene YAML: fly the tour (flown_tour.hpp) with its checks.
  std::uint64_t build_samples = 0;  ///< With scene: N of the roadmap's build, for the corridor's density.
  bool json = false;
  std::string out;
};
CLI::App* add_tour_command(CLI::App& parent, TourCommandOptions& options);
int run_tour(const TourCommandOptions& options);

struct RenderCommandOptions {
  std::string scene;    ///< The scene YAML.
  std::string roadmap;  ///< A roadmap file (optional).
  bool dense = false;   ///< Also draw the file's dense graph, faint.
  std::string tour;     ///< A tour file (ispars-lab tour --out), optional.
  std::string out;      ///< The PNG to write.
  int width = 1600;
  int height = 1200;
  std::vector<double> eye;     ///< Camera position (3 numbers), or framed automatically.
  std::vector<double> target;  ///< Camera target (3 numbers).
  double fov = 45.0;
  std::size_t max_edges = 2'000'000;
  bool json = false;
};
CLI::App* add_render_command(CLI::App& parent, RenderCommandOptions& options);
int run_render(const RenderCommandOptions& options);

CLI::App* add_experiment_table_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_table(const ExperimentOptions& options);
CLI::App* add_experiment_scaling_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_scaling(const ExperimentOptions& options);
CLI::App* add_experiment_spanner_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_spanner(const ExperimentOptions& options);
CLI::App* add_experiment_anytime_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_anytime(const ExperimentOptions& options);
CLI::App* add_experiment_flown_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_flown(const ExperimentOptions& options);
CLI::App* add_experiment_ablation_command(CLI::App& parent, ExperimentOptions& options);
int run_experiment_ablation(const ExperimentOptions& options);

}  // namespace ispars::lab
