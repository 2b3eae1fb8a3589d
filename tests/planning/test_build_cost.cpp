// The build cost estimate: an upper bound on what a roadmap holds, close enough to refuse only
// what is truly too big.

#include <gtest/gtest.h>

#include "ispars/planning/builders/build_cost.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

struct Case {
  const char* scene;
  BuildMethod method;
  std::uint64_t samples;
};

TEST(BuildCost, TheEstimateBoundsTheBuiltGraphFromAboveAndWithinAFewTimes) {
  for (const Case& c :
       {Case{"demo_tank_tower", BuildMethod::dense, 4000}, Case{"water_tower", BuildMethod::dense, 3000},
        Case{"truss_bridge", BuildMethod::ispars, 3000}, Case{"demo_tank_tower", BuildMethod::irisc, 3000},
        Case{"water_tower", BuildMethod::ispars2, 20000}, Case{"caric_city", BuildMethod::ispars2, 20000}}) {
    const Scene& scene = test::shared_scene(c.scene);
    BuildOptions options;
    options.seed = 5;
    const auto builder = make_roadmap_builder(c.method, scene, options);
    builder->extend(c.samples);
    const Roadmap& graph = builder->dense() ? *builder->dense() : builder->roadmap();
    RoadmapRecipe recipe;
    recipe.method = c.method;
    recipe.dense_delta = scene.config().dense_delta;
    recipe.sparse_delta = scene.config().sparse_delta;
    const double f = free_fraction(scene);
    EXPECT_GT(f, 0.0);
    EXPECT_LE(f, 1.0);
    EXPECT_EQ(f, free_fraction(scene)) << "the same scene gives the same fraction";
    const BuildCost cost = estimate_build_cost(scene, recipe, c.samples, f);
    const auto label = std::string(c.scene) + " " + std::string(to_string(c.method));
    // Vertices: the free fraction is itself estimated, so allow it a few percent.
    EXPECT_GE(cost.vertices, 0.95 * static_cast<double>(graph.vertex_count())) << label;
    EXPECT_GE(cost.edges, static_cast<double>(graph.edge_count())) << label;
    EXPECT_LE(cost.edges, 3.0 * static_cast<double>(graph.edge_count()) + 1000.0) << label << ": far too cautious";
    EXPECT_GE(cost.bytes, static_cast<double>(graph.edge_count()) * kBytesPerEdge) << label;
    // The peak adds a compaction fold of everything stored: the graph's vertices (as estimated,
    // see above) and edges again.
    EXPECT_GE(cost.peak_bytes - cost.bytes, 0.95 * static_cast<double>(graph.vertex_count()) * kFoldBytesPerVertex +
                                                static_cast<double>(graph.edge_count()) * kFoldBytesPerEdge)
        << label;
  }
}

TEST(BuildCost, AHugeDeltaCountsEveryPairAndMoreSamplesNeverCostLess) {
  const Scene& scene = test::shared_scene("demo_tank_tower");
  const double f = free_fraction(scene);
  RoadmapRecipe recipe;
  recipe.method = BuildMethod::dense;
  recipe.dense_delta = 1e6;
  const BuildCost all_pairs = estimate_build_cost(scene, recipe, 100'000, f);
  EXPECT_NEAR(all_pairs.edges, all_pairs.vertices * (all_pairs.vertices - 1) / 2, 1.0);
  EXPECT_GT(all_pairs.bytes, 100e9) << "100,000 samples all within delta is hundreds of GB";
  double last = 0.0;
  for (const std::uint64_t n : {1ull, 10ull, 1000ull, 1'000'000ull, 50'000'000ull}) {
    recipe.method = BuildMethod::ispars;
    recipe.dense_delta = scene.config().dense_delta;
    const BuildCost cost = estimate_build_cost(scene, recipe, n, f);
    EXPECT_GE(cost.peak_bytes, last) << n;
    EXPECT_GE(cost.peak_bytes, cost.bytes) << n;
    last = cost.peak_bytes;
  }
  EXPECT_EQ(estimate_build_cost(scene, recipe, 0, f).bytes, 0.0);
  EXPECT_EQ(estimate_build_cost(scene, recipe, 0, f).peak_bytes, 0.0);
}

}  // namespace
}  // namespace ispars::planning
