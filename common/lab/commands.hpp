#pragma once
// The lab's subcommands. Each prints a human report, or with `json` one JSON object as the last
// line of stdout; bad input surfaces as ispars::InputError for main() to report.

#include <cstdint>
#include <string>

namespace ispars::lab {

struct SceneInfoOptions {
  std::string scene;
  bool json = false;
  std::size_t samples = 10'000;  ///< Random valid configurations for the coverage estimate.
  std::uint64_t seed = 1;
};
int run_scene_info(const SceneInfoOptions& options);

struct BenchGeometryOptions {
  std::string scene;
  bool json = false;
  std::size_t queries = 20'000;          ///< Queries per fast-path measurement.
  std::size_t reference_queries = 200;   ///< Queries through the brute-force reference.
  std::uint64_t seed = 1;
};
int run_bench_geometry(const BenchGeometryOptions& options);

struct BuildCommandOptions {
  std::string scene;
  std::string method;
  std::size_t samples = 1000;
  std::uint64_t seed = 1;
  unsigned threads = 1;
  double p_accept = 0.2;
  bool verify = false;
  bool json = false;
  std::string out;   ///< --out FILE.json: the roadmap (and its dense pair) in full.
  std::string iris;  ///< --iris PREFIX: IRIS text files PREFIX_vertex, _edge, _conf.
};
int run_build(const BuildCommandOptions& options);

struct BenchBuildOptions {
  std::string scene;
  std::string method = "ispars";
  std::size_t samples = 20'000;
  std::size_t checkpoints = 10;
  std::uint64_t seed = 1;
  unsigned threads = 1;
  bool json = false;
};
int run_bench_build(const BenchBuildOptions& options);

struct ExperimentOptions {
  std::string scenes_dir = ISPARS_DEFAULT_SCENES_DIR;
  std::uint64_t seeds = 6;
  unsigned threads = 2;
  bool json = false;
  // scaling
  std::string scene = "water_tower";
  std::size_t max_samples = 20'000;
  std::size_t pois = 100;
  double delta = 0.0;  ///< 0: calibrate to the paper's density (water tower: degree 7.36 at N = 4000)
  std::string csv;
  std::string png;
  // spanner
  std::size_t samples = 4000;
  std::size_t pairs = 1000;
  // anytime
  double budget = 30.0;
  unsigned jobs = 2;
};
struct TourCommandOptions {
  std::string roadmap;         ///< A roadmap file (ispars-lab build --out / ispars snapshot --out).
  std::string graph = "roadmap";
  std::string iris;            ///< Or IRIS files PREFIX_vertex, PREFIX_edge.
  bool all_edges = false;      ///< IRIS: keep edges marked invalid too.
  double budget = 10.0;
  std::uint64_t seed = 1;
  unsigned threads = 1;
  std::uint64_t iterations = 0;
  bool json = false;
  std::string out;
};
int run_tour(const TourCommandOptions& options);

int run_experiment_table(const ExperimentOptions& options);
int run_experiment_scaling(const ExperimentOptions& options);
int run_experiment_spanner(const ExperimentOptions& options);
int run_experiment_anytime(const ExperimentOptions& options);

}  // namespace ispars::lab
