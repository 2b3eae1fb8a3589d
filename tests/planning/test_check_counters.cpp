// Check counters count exactly the calls made, from any number of threads.

#include <gtest/gtest.h>

#include <thread>

#include "ispars/planning/geometry/check_counters.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/scene_files/procedural.hpp"

namespace ispars::planning {
namespace {

TEST(CheckCounters, CountEveryCallAcrossThreads) {
  const CheckCounters counters;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 10000; ++i) {
        counters.add_point();
        counters.add_segment();
        counters.add_rays(3);
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(counters.snapshot(), (CheckCounts{40000, 40000, 120000}));
}

TEST(CheckCounters, SceneCountsItsQueries) {
  const Scene scene = Scene::build(scene_files::procedural_scene_config("tank_tower", 1));
  const CheckCounts before = scene.counts();
  (void)scene.point_valid(Vec3(8, 0, 3));
  (void)scene.point_valid(Vec3(8, 1, 3));
  (void)scene.segment_valid(Vec3(8, 0, 3), Vec3(8, 1, 3));
  std::vector<PoiId> in_range;
  scene.visibility().pois_in_range(Vec3(4, 0, 10), in_range);
  const auto chi = scene.visibility().visible_pois(Vec3(4, 0, 10));
  const CheckCounts used = scene.counts() - before;
  EXPECT_EQ(used.point, 2u);
  EXPECT_EQ(used.segment, 1u);
  EXPECT_EQ(used.rays, in_range.size());  // one ray per POI in range, none for the rest
  EXPECT_GT(used.rays, 0u);
}

}  // namespace
}  // namespace ispars::planning
