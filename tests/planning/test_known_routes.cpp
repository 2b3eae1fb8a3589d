// The stretch rules' route cache: pairs in either order, the shorter route kept, everything kept
// through growth, a bound on what it holds, and (the point of it being a cache) the same roadmap
// however small it is.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "ispars/planning/builders/known_routes.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

TEST(KnownRoutes, RemembersPairsInEitherOrderAndKeepsTheShorterRoute) {
  KnownRoutes routes(2048);
  EXPECT_TRUE(std::isinf(routes.get(3, 7)));
  routes.remember(7, 3, 5.0);
  EXPECT_EQ(routes.get(3, 7), 5.0);
  EXPECT_EQ(routes.get(7, 3), 5.0);
  routes.remember(3, 7, 6.0);
  EXPECT_EQ(routes.get(3, 7), 5.0) << "a longer route replaced a shorter one";
  routes.remember(3, 7, 4.0);
  EXPECT_EQ(routes.get(7, 3), 4.0);
  routes.remember(9, 9, 1.0);  // a vertex to itself is no pair
  EXPECT_EQ(routes.size(), 1u);
  EXPECT_TRUE(std::isinf(routes.get(0, 3)));
}

TEST(KnownRoutes, KeepsEveryPairThroughGrowthThenTheYoungerGenerationOnly) {
  KnownRoutes routes(1 << 16);
  // Keys that collide in the low bits, and vertex 0 (whose pairs have keys below 2^32).
  for (VertexId a = 0; a < 200; ++a) {
    for (VertexId b = a + 1; b < a + 150; ++b) routes.remember(a, b * 1024, a + b / 1000.0);
  }
  EXPECT_EQ(routes.size(), 200u * 149u);
  for (VertexId a = 0; a < 200; ++a) {
    for (VertexId b = a + 1; b < a + 150; ++b) ASSERT_EQ(routes.get(b * 1024, a), a + b / 1000.0) << a << " " << b;
  }
  EXPECT_EQ(routes.generations_dropped(), 0u);
  // Past half of the bound the pairs above become the old generation, still answered...
  VertexId next = 1'000'000;
  const auto fill_generation = [&] {
    for (const std::size_t dropped = routes.generations_dropped(); routes.generations_dropped() == dropped; ++next) {
      routes.remember(next, next + 1, 1.0);
    }
  };
  fill_generation();
  EXPECT_EQ(routes.get(0, 1024), 0.001);
  routes.remember(0, 1024, 0.0005);  // a shorter route, remembered young, wins
  routes.remember(0, 1024, 0.7);     // a longer one does not
  EXPECT_EQ(routes.get(1024, 0), 0.0005);
  // ...and forgotten when the next one is full, while the bound holds.
  fill_generation();
  EXPECT_TRUE(std::isinf(routes.get(1, 2048)));
  EXPECT_EQ(routes.get(0, 1024), 0.0005) << "a pair remembered again is young";
  EXPECT_LE(routes.size(), std::size_t{1} << 16);
  EXPECT_THROW(KnownRoutes(2047), std::invalid_argument);
  EXPECT_THROW(KnownRoutes((std::size_t{1} << 30) + 1), std::invalid_argument);
}

TEST(KnownRoutes, ATinyCacheGrowsTheSameRoadmapAsALargeOne) {
  const Scene& scene = test::shared_scene("water_tower");
  BuildOptions small;
  small.known_route_pairs = 2048;
  BuildOptions large;
  const auto a = make_roadmap_builder(BuildMethod::ispars2, scene, small);
  const auto b = make_roadmap_builder(BuildMethod::ispars2, scene, large);
  a->extend(8000);
  b->extend(8000);
  EXPECT_EQ(roadmap_digest(a->roadmap()), roadmap_digest(b->roadmap()));
  EXPECT_GT(a->roadmap().edge_count(), 2048u) << "the small cache never filled: the test would prove nothing";
}

}  // namespace
}  // namespace ispars::planning
