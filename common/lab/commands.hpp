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

struct BuildOptions {
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
int run_build(const BuildOptions& options);

}  // namespace ispars::lab
