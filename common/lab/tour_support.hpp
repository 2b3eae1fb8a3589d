#pragma once
// Shared pieces of the lab's tour experiments: the common target set, the Dense graph seen only
// from chosen viewpoints, and solving several graphs with the same solver work.

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/planning/tour/tour_bound.hpp"
#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::lab {

/// POIs seen by some vertex of the root's component.
[[nodiscard]] std::vector<PoiId> seen_from_root(const InspectionGraph& graph);

/// I_t: the POIs seen from the root's component in every graph.
[[nodiscard]] std::vector<PoiId> common_targets(std::span<const InspectionGraph* const> graphs);

/// The dense roadmap as a tour graph in which only `viewpoints` (dense ids) see POIs: Dense
/// routing with a sparse roadmap's viewpoints. Separates "viewpoints lost" from "routing lost".
[[nodiscard]] InspectionGraph with_viewpoints(const Roadmap& dense, std::span<const VertexId> viewpoints);

/// Runs job(i) for i in [0, count) on `jobs` threads (the caller's included), each taking the
/// next index; after a job throws, no new one starts and the first error is rethrown.
template <class Job>
void run_jobs(std::size_t count, unsigned jobs, Job&& job) {
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::string failure;
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < count;) {
      {
        std::lock_guard lock(mutex);
        if (!failure.empty()) return;
      }
      try {
        job(i);
      } catch (const std::exception& e) {
        std::lock_guard lock(mutex);
        if (failure.empty()) failure = e.what();
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned j = 1; j < std::max(1u, jobs); ++j) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (!failure.empty()) throw std::runtime_error(failure);
}

/// The same solver work for every graph: an iteration cap (deterministic, the same on any
/// machine) with a wall-clock cap as a safety net, one solver thread per graph, `jobs` graphs
/// at a time.
struct SolverWork {
  std::uint64_t iterations = 30'000;
  double cap_seconds = 600.0;
  unsigned jobs = 2;
};

/// Solves each graph for `targets` with `work`; throws std::runtime_error on a solver failure or
/// an invalid tour. result[i] belongs to graphs[i].
[[nodiscard]] std::vector<planning::GipResult> solve_each(std::span<const InspectionGraph* const> graphs,
                                                          const std::vector<PoiId>& targets, std::uint64_t seed,
                                                          const SolverWork& work);

/// The LP lower bound (tour_bound.hpp) of each graph for `targets`, `seconds` of wall clock
/// each, `jobs` graphs at a time. result[i] belongs to graphs[i].
[[nodiscard]] std::vector<planning::TourBoundResult> bound_each(std::span<const InspectionGraph* const> graphs,
                                                                const std::vector<PoiId>& targets, double seconds,
                                                                unsigned jobs);

/// True when the run stopped at the wall-clock cap, before its iteration cap.
[[nodiscard]] bool hit_time_cap(const planning::GipResult& result, const SolverWork& work);

/// A rule set by name: "alg1" or "stretch", then any of "+R" / "-R" with R in join, witness,
/// shortcut (e.g. "alg1+join", "stretch+shortcut"). Throws InputError (field `field`) otherwise.
[[nodiscard]] planning::SparsRules parse_rule_set(const std::string& name, const std::string& field);

}  // namespace ispars::lab
