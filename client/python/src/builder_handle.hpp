#pragma once
// ispars.Builder: a roadmap under construction from Python, grown by extend() off the GIL.

#include <atomic>
#include <memory>
#include <string>

#include "ispars/params/spec.hpp"
#include "ispars/planning/builders/build_cost.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "python_module.hpp"
#include "stoppable.hpp"

namespace ispars::python {

/// What a Builder's roadmap may be expected to hold: an extend whose estimate (build_cost.hpp,
/// the daemon's, an upper estimate) is past it is refused before it starts.
inline constexpr params::Spec<std::uint64_t> kMemoryMb{
    "memory_mb", 0, std::uint64_t{1} << 30,
    "MiB the roadmap may be expected to hold (0: half of this machine's memory); a larger extend is refused",
    params::Lower::closed};

/// A builder with its recipe and scenes. One call at a time: a second call while extend() or
/// verify() runs (from another thread) raises RuntimeError rather than wait.
class BuilderHandle {
 public:
  BuilderHandle(std::shared_ptr<planning::Scene> scene, const std::string& method, std::uint64_t seed,
                const std::string& variant, std::int64_t threads, const py::dict& overrides,
                std::uint64_t memory_mb = 0);

  /// Draws `samples` more samples; returns how many it drew (fewer when stopped).
  std::uint64_t extend(std::int64_t samples, const std::shared_ptr<StopFlag>& stop, const py::object& progress);
  /// The estimate of the roadmap after `samples` more samples.
  planning::BuildCost expected_cost(std::uint64_t samples);
  /// The memory limit in bytes (memory_mb, or half of physical memory).
  [[nodiscard]] double memory_limit() const { return memory_limit_; }
  /// A copy of the roadmap as it is (made once per state, then shared).
  std::shared_ptr<Roadmap> roadmap();
  /// A copy of the dense pair, or nullptr.
  std::shared_ptr<Roadmap> dense();
  /// For each roadmap vertex its dense vertex (empty without a dense pair).
  py::array_t<std::uint32_t> dense_ids();
  /// verify_recipe_roadmaps, as a dict of counts.
  py::dict verify(const std::shared_ptr<StopFlag>& stop);
  [[nodiscard]] py::dict recipe() const;
  [[nodiscard]] std::uint64_t samples() const { return builder_->samples(); }
  [[nodiscard]] const std::shared_ptr<planning::Scene>& base_scene() const { return base_; }

 private:
  class Busy;
  std::shared_ptr<planning::Scene> base_;
  RoadmapRecipe recipe_;
  std::unique_ptr<planning::Scene> scene_;  // base_ with the recipe's parameters; outlives builder_
  unsigned threads_ = 1;
  std::unique_ptr<planning::RoadmapBuilder> builder_;
  std::atomic<bool> busy_{false};
  std::shared_ptr<Roadmap> roadmap_copy_, dense_copy_;  // of the current state; reset by extend
  double memory_limit_ = 0.0;
  double free_fraction_ = -1.0;  // of the scene, probed on the first estimate
};

/// Binds Builder and the build() shortcut.
void bind_builder(py::module_& m);

}  // namespace ispars::python
