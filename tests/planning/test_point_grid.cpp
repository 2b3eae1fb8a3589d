// PointGrid radius queries against a scan, including points exactly on the radius.

#include <gtest/gtest.h>

#include <cmath>

#include "ispars/planning/geometry/point_grid.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

TEST(PointGrid, RadiusQueriesMatchAScanInOrder) {
  scene_files::Rng rng(4);
  std::vector<Vec3> points;
  PointGrid grid(1.5);
  for (std::uint32_t i = 0; i < 3000; ++i) {
    points.push_back(rng.uniform_in({Vec3(-20, -20, -5), Vec3(20, 20, 5)}));
    grid.insert(i, points.back());
  }
  std::vector<std::pair<double, std::uint32_t>> found;
  for (int k = 0; k < 300; ++k) {
    const Vec3 q = rng.uniform_in({Vec3(-22, -22, -6), Vec3(22, 22, 6)});
    const double radius = rng.uniform(0.1, 6.0);
    grid.within(q, radius, points, found);
    std::vector<std::pair<double, std::uint32_t>> expected;
    for (std::uint32_t i = 0; i < points.size(); ++i) {
      const double d2 = (points[i] - q).squaredNorm();
      if (d2 <= radius * radius) expected.emplace_back(std::sqrt(d2), i);
    }
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(found, expected);
  }
}

TEST(PointGrid, TheRadiusIsInclusive) {
  std::vector<Vec3> points{Vec3(2, 0, 0), Vec3(-2, 0, 0), Vec3(0, 2.0000001, 0)};
  PointGrid grid(1.0);
  for (std::uint32_t i = 0; i < points.size(); ++i) grid.insert(i, points[i]);
  std::vector<std::pair<double, std::uint32_t>> found;
  grid.within(Vec3(0, 0, 0), 2.0, points, found);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_EQ(found[0].second, 0u);  // equal distances: lower id first
  EXPECT_EQ(found[1].second, 1u);
}

}  // namespace
}  // namespace ispars::planning
