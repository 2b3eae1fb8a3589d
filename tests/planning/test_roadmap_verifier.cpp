// The roadmap verifier: clean on a built roadmap, and stoppable between small steps.

#include <gtest/gtest.h>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

TEST(RoadmapVerifier, ABuiltPairIsCleanAndAStopIsHeardWithin256Steps) {
  const Scene& scene = test::shared_scene("truss_bridge");
  BuildOptions options;
  options.seed = 3;
  auto builder = make_roadmap_builder(BuildMethod::ispars, scene, options);
  builder->extend(2000);
  const VerificationReport clean =
      verify_sparse_pair(scene, builder->roadmap(), *builder->dense(), builder->dense_ids());
  EXPECT_TRUE(clean.geometry_ok());
  EXPECT_EQ(clean.invariant_violations, 0u);
  for (const std::size_t allowed : {std::size_t{0}, std::size_t{1}, std::size_t{5}}) {
    std::size_t asked = 0;
    const VerifyKeepGoing keep_going = [&] { return asked++ < allowed; };
    EXPECT_THROW(
        (void)verify_sparse_pair(scene, builder->roadmap(), *builder->dense(), builder->dense_ids(), keep_going),
        VerificationStopped);
    EXPECT_EQ(asked, allowed + 1) << "it went on after a stop";
  }
  std::size_t asked = 0;
  EXPECT_THROW((void)verify_fresh_samples(scene, builder->roadmap(), 5000, 1, [&] { return asked++ < 3; }),
               VerificationStopped);
  // Asked at least once per 256 steps: a full run asks about (vertices + edges + samples) / 256.
  asked = 0;
  (void)verify_roadmap(scene, *builder->dense(), [&] { return ++asked > 0; });
  EXPECT_GE(asked, (builder->dense()->vertex_count() + builder->dense()->edge_count()) / 256);
}

}  // namespace
}  // namespace ispars::planning
