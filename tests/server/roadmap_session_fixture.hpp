#pragma once
// The roadmap session's test fixture: a session on the demo tank tower, in a temporary directory.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <memory>

#include "ispars/service/roadmap_session.hpp"
#include "support/test_support.hpp"

namespace ispars::service {

/// The digest of the roadmap an uninterrupted build of `samples` samples with `seed` makes:
/// what a session's roadmap must equal however its job was cut and resumed.
inline std::uint64_t uninterrupted_digest(const planning::Scene& scene, std::uint64_t samples, std::uint64_t seed,
                                          BuildMethod method = BuildMethod::ispars) {
  planning::BuildOptions options;
  options.seed = seed;
  auto builder = planning::make_roadmap_builder(method, scene, options);
  builder->extend(samples);
  return roadmap_digest(builder->roadmap());
}

class RoadmapSessionTest : public ::testing::Test {
 protected:
  std::unique_ptr<RoadmapSession> open(SessionCallbacks callbacks = {}, SessionLimits limits = {}) {
    return std::make_unique<RoadmapSession>("tower", scene(), dir_.path() / "tower", limits, std::move(callbacks));
  }
  static const planning::Scene& scene() { return test::shared_scene("demo_tank_tower"); }
  // A roadmap whose verify runs long enough to be caught running: 20,000 samples, and 5,000 in
  // the sanitizer pass (ISPARS_TEST_QUERY_SCALE), where builds and verifies run about 10x slower.
  static std::uint64_t busy_samples() { return std::max<std::size_t>(5000, test::scaled(20000)); }
  static BuildRequest ispars(std::uint64_t samples, std::uint64_t seed = 1) {
    BuildRequest r;
    r.method = BuildMethod::ispars;
    r.samples = samples;
    r.seed = seed;
    return r;
  }
  test::TempDir dir_;
  std::atomic<bool> never_{false};
};

}  // namespace ispars::service
