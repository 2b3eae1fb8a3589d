// VisibilityOracle against brute-force line of sight over all triangles and all POIs.

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "ispars/reference/brute_force.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// Valid configurations within sensor range of a random POI, where chi(q) is not trivially empty.
std::vector<Vec3> near_structure_configurations(const Scene& scene, scene_files::Rng& rng, std::size_t count) {
  std::vector<Vec3> out;
  while (out.size() < count) {
    const Vec3& poi = scene.pois()[rng.below(scene.pois().size())];
    const Vec3 q = poi + rng.uniform(0.0, scene.config().sensor_range) * rng.unit_vector();
    if (scene.point_valid(q)) out.push_back(q);
  }
  return out;
}

class VisibilityAgreement : public ::testing::TestWithParam<std::pair<std::string, std::size_t>> {};

TEST_P(VisibilityAgreement, ChiMatchesBruteForceOutsideTheToleranceBand) {
  const Scene& scene = test::shared_scene(GetParam().first);
  const reference::BruteForceGeometry brute(scene.embree().triangles(), scene.config().bounds,
                                            scene.config().robot_radius, scene.pois(), scene.config().sensor_range);
  scene_files::Rng rng(21);
  const auto configurations = near_structure_configurations(scene, rng, test::scaled(GetParam().second));
  std::size_t visible_total = 0;
  std::size_t blocked_total = 0;
  std::size_t ambiguous_total = 0;
  std::vector<PoiId> chi;
  std::vector<PoiId> in_range;
  for (const Vec3& q : configurations) {
    std::vector<PoiId> ambiguous;
    const std::vector<PoiId> expected = brute.visible_pois(q, &ambiguous);
    scene.visible_pois(q, chi);
    ASSERT_TRUE(std::is_sorted(chi.begin(), chi.end()));
    std::vector<PoiId> differ;
    std::set_symmetric_difference(chi.begin(), chi.end(), expected.begin(), expected.end(), std::back_inserter(differ));
    for (const PoiId id : differ) {
      EXPECT_TRUE(std::binary_search(ambiguous.begin(), ambiguous.end(), id))
          << "POI " << id << " from " << q.transpose() << ": fast says "
          << std::binary_search(chi.begin(), chi.end(), id);
    }
    scene.visibility().pois_in_range(q, in_range);
    visible_total += expected.size();
    blocked_total += in_range.size() - expected.size();
    ambiguous_total += ambiguous.size();
  }
  // Both outcomes must occur often, and the band must stay a sliver.
  EXPECT_GT(visible_total, configurations.size());
  EXPECT_GT(blocked_total, configurations.size() / 4);
  EXPECT_LT(ambiguous_total * 1000, visible_total + blocked_total + 1000);
}

INSTANTIATE_TEST_SUITE_P(Scenes, VisibilityAgreement,
                         ::testing::Values(std::pair<std::string, std::size_t>{"water_tower", 1500},
                                           std::pair<std::string, std::size_t>{"truss_bridge", 1500},
                                           std::pair<std::string, std::size_t>{"radio_tower", 1000},
                                           std::pair<std::string, std::size_t>{"powerplant", 400},
                                           std::pair<std::string, std::size_t>{"caric_city", 120}),
                         [](const auto& case_info) { return case_info.param.first; });

TEST(Visibility, PoisInRangeMatchesAScanIncludingTheBoundary) {
  const Scene& scene = test::shared_scene("water_tower");
  scene_files::Rng rng(3);
  std::vector<PoiId> found;
  const double range = scene.config().sensor_range;
  for (int i = 0; i < 500; ++i) {
    const Vec3 q = rng.uniform_in(scene.config().bounds);
    scene.visibility().pois_in_range(q, found);
    std::vector<PoiId> expected;
    for (std::size_t k = 0; k < scene.pois().size(); ++k) {
      if ((scene.pois()[k] - q).squaredNorm() <= range * range) expected.push_back(static_cast<PoiId>(k));
    }
    ASSERT_EQ(found, expected);
  }
}

// A wall at z = 0 over a floor at z = -2; POIs on the floor, one of them under the wall.
Scene wall_scene(const test::TempDir& dir) {
  scene_files::TriangleMesh mesh;
  mesh.vertices = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-4, -4, -2}, {4, -4, -2}, {4, 4, -2}, {-4, 4, -2}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  scene_files::SceneConfig config;
  config.source = "test";
  config.bounds = {Vec3(-5, -5, -5), Vec3(5, 5, 5)};
  config.robot_radius = 0.1;
  config.sensor_range = 3.5;
  config.dense_delta = 1;
  config.sparse_delta = 1.5;
  config.stretch = 1.05;
  config.root = Vec3(4, 4, 4);
  config.pois.file = dir.write("pois.txt", "0 0 -2\n3.5 -3 -2  # near a corner\n");
  return Scene::build(config, mesh);
}

TEST(Visibility, WallBlocksSightAndRangeLimitsIt) {
  const test::TempDir dir;
  const Scene scene = wall_scene(dir);
  ASSERT_EQ(scene.pois().size(), 2u);
  // Above the wall: POI 0 is hidden under it, POI 1 is out of range.
  EXPECT_TRUE(scene.visibility().visible_pois(Vec3(0, 0, 1)).empty());
  // Beside the wall, below its plane: both seen (their own floor does not block them).
  EXPECT_EQ(scene.visibility().visible_pois(Vec3(3, 0, -1)), (std::vector<PoiId>{0, 1}));
  EXPECT_FALSE(scene.visibility().line_of_sight(Vec3(0, 0, 1), 0));
  EXPECT_TRUE(scene.visibility().line_of_sight(Vec3(0, 0, 1), 1));  // in sight, though out of range
}

TEST(Visibility, ConcurrentChiEqualsSerial) {
  const Scene& scene = test::shared_scene("truss_bridge");
  scene_files::Rng rng(9);
  std::vector<Vec3> qs;
  for (int i = 0; i < 2000; ++i) qs.push_back(scene.sample_valid_configuration(rng));
  std::vector<std::vector<PoiId>> serial(qs.size());
  for (std::size_t i = 0; i < qs.size(); ++i) serial[i] = scene.visibility().visible_pois(qs[i]);
  std::vector<std::vector<PoiId>> parallel(qs.size());
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < 3; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t i = t; i < qs.size(); i += 3) parallel[i] = scene.visibility().visible_pois(qs[i]);
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace ispars::planning
