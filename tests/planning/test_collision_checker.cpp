// CollisionChecker against the brute-force reference, on every shared scene and the procedural
// structures, plus the corner cases (degenerate triangles, bounds, threads).

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <thread>

#include "ispars/reference/brute_force.hpp"
#include "ispars/scene_files/procedural.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// Decisions may differ only where the exact distance is within this of the radius: there the
// float culling and the double test could in principle disagree. Every case outside the band
// must agree, and the band is reported so a growing band shows.
constexpr double kBand = 1e-7;

struct AgreementCase {
  std::string scene;
  std::size_t points;
  std::size_t segments;
};

void PrintTo(const AgreementCase& c, std::ostream* os) { *os << c.scene; }

// "procedural_KIND" names a generated structure (seed 3); anything else a shared scene.
const Scene& scene_for(const std::string& name) {
  const std::string prefix = "procedural_";
  if (name.rfind(prefix, 0) == 0) {
    static std::map<std::string, std::unique_ptr<Scene>> cache;
    auto& slot = cache[name];
    if (!slot)
      slot = std::make_unique<Scene>(Scene::build(scene_files::procedural_scene_config(name.substr(prefix.size()), 3)));
    return *slot;
  }
  return test::shared_scene(name);
}

reference::BruteForceGeometry reference_for(const Scene& scene) {
  return reference::BruteForceGeometry(scene.embree().triangles(), scene.config().bounds, scene.config().robot_radius,
                                       scene.pois(), scene.config().sensor_range);
}

class CollisionAgreement : public ::testing::TestWithParam<AgreementCase> {};

TEST_P(CollisionAgreement, PointChecksMatchBruteForce) {
  const Scene& scene = scene_for(GetParam().scene);
  const reference::BruteForceGeometry brute = reference_for(scene);
  scene_files::Rng rng(11);
  const auto points = test::mixed_query_points(scene, rng, test::scaled(GetParam().points));
  std::size_t disagreements = 0;
  std::size_t in_band = 0;
  std::size_t invalid = 0;
  const double r = scene.config().robot_radius;
  for (const Vec3& p : points) {
    const double distance = brute.distance_to_surface(p);
    const bool expected = scene.config().bounds.contains(p) && distance > r;
    invalid += !expected;
    if (std::abs(distance - r) <= kBand) {
      ++in_band;
      continue;
    }
    if (scene.point_valid(p) != expected) {
      ++disagreements;
      ADD_FAILURE() << "point " << p.transpose() << " distance " << distance << " radius " << r;
    }
    // The exact clearance agrees too (same double arithmetic on the same triangles).
    EXPECT_NEAR(scene.collision().distance_to_surface(p), distance, 1e-9 * (1 + distance));
  }
  EXPECT_EQ(disagreements, 0u);
  // The queries must exercise both answers, or the agreement says little.
  EXPECT_GT(invalid, points.size() / 10);
  EXPECT_LT(invalid, points.size());
  RecordProperty("in_band", static_cast<int>(in_band));
}

TEST_P(CollisionAgreement, SegmentChecksMatchBruteForce) {
  const Scene& scene = scene_for(GetParam().scene);
  const reference::BruteForceGeometry brute = reference_for(scene);
  scene_files::Rng rng(12);
  const auto segments = test::mixed_query_segments(scene, rng, test::scaled(GetParam().segments));
  const double r = scene.config().robot_radius;
  std::size_t invalid = 0;
  for (const auto& s : segments) {
    const double distance = brute.segment_distance_to_surface(s.a, s.b);
    const bool expected = distance > r;  // the test segments stay inside the bounds
    invalid += !expected;
    if (std::abs(distance - r) <= kBand) continue;
    EXPECT_EQ(scene.segment_valid(s.a, s.b), expected)
        << "segment " << s.a.transpose() << " -> " << s.b.transpose() << " distance " << distance;
    EXPECT_EQ(brute.segment_valid(s.a, s.b), expected);
  }
  EXPECT_GT(invalid, segments.size() / 10);
  EXPECT_LT(invalid, segments.size());
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, CollisionAgreement,
    ::testing::Values(AgreementCase{"water_tower", 4000, 3000}, AgreementCase{"truss_bridge", 4000, 3000},
                      AgreementCase{"radio_tower", 4000, 3000}, AgreementCase{"powerplant", 3000, 2000},
                      AgreementCase{"caric_city", 1500, 1000}, AgreementCase{"procedural_truss_bridge", 3000, 3000},
                      AgreementCase{"procedural_tank_tower", 3000, 3000},
                      AgreementCase{"procedural_city_grid", 3000, 3000}),
    [](const auto& case_info) { return case_info.param.scene; });

// A scene with one triangle, for exact hand-made cases.
Scene single_triangle_scene(const Triangle& t, double radius) {
  // Plus a far-away tile in a corner, so POIs have surface to be sampled on.
  scene_files::TriangleMesh mesh;
  mesh.vertices = {t.a.cast<float>(), t.b.cast<float>(), t.c.cast<float>(), {-9, -9, -9}, {-8, -9, -9}, {-9, -8, -9}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  scene_files::SceneConfig config;
  config.source = "test";
  config.bounds = {Vec3(-10, -10, -10), Vec3(10, 10, 10)};
  config.robot_radius = radius;
  config.sensor_range = 5;
  config.dense_delta = 1;
  config.sparse_delta = 1.5;
  config.stretch = 1.05;
  config.root = Vec3(9, 9, 9);
  config.pois = scene_files::PoiSource{1, 1, false, {}};
  return Scene::build(config, mesh);
}

TEST(CollisionChecker, SegmentPassingThroughTriangleIsInvalidEvenWithWideSpacing) {
  // A segment far longer than the radius that pierces a small triangle in its middle: any
  // discretised walk with steps above the triangle's size would miss it.
  const Scene scene = single_triangle_scene({Vec3(-0.01, -0.01, 0), Vec3(0.01, -0.01, 0), Vec3(0, 0.01, 0)}, 0.001);
  EXPECT_TRUE(scene.point_valid(Vec3(0, 0, 5)));
  EXPECT_TRUE(scene.point_valid(Vec3(0, 0, -5)));
  EXPECT_FALSE(scene.segment_valid(Vec3(0, 0, 5), Vec3(0, 0, -5)));
  EXPECT_TRUE(scene.segment_valid(Vec3(0.5, 0, 5), Vec3(0.5, 0, -5)));
}

TEST(CollisionChecker, RadiusBoundaryIsCollision) {
  // Distance exactly r counts as touching; a hair more is free.
  const Scene scene = single_triangle_scene({Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}, 0.5);
  EXPECT_FALSE(scene.point_valid(Vec3(0, 0, 0.5)));
  EXPECT_TRUE(scene.point_valid(Vec3(0, 0, 0.5 + 1e-9)));
  EXPECT_FALSE(scene.segment_valid(Vec3(-3, 0, 0.5), Vec3(3, 0, 0.5)));
  EXPECT_TRUE(scene.segment_valid(Vec3(-3, 0, 0.5 + 1e-9), Vec3(3, 0, 0.5 + 1e-9)));
}

TEST(CollisionChecker, DegenerateTriangleIsStillAnObstacle) {
  // Zero-area triangles (83 in caric_city) are line obstacles; they must not vanish.
  const Scene scene = single_triangle_scene({Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(1, 0, 0)}, 0.2);
  EXPECT_FALSE(scene.point_valid(Vec3(0.5, 0.1, 0)));
  EXPECT_TRUE(scene.point_valid(Vec3(0.5, 0.3, 0)));
  EXPECT_FALSE(scene.segment_valid(Vec3(0.5, 0, 2), Vec3(0.5, 0, -2)));
  EXPECT_NEAR(scene.collision().distance_to_surface(Vec3(0.5, 0, 1)), 1.0, 1e-12);
}

TEST(CollisionChecker, OutsideBoundsIsInvalid) {
  const Scene scene = single_triangle_scene({Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}, 0.5);
  EXPECT_FALSE(scene.point_valid(Vec3(0, 0, 11)));
  EXPECT_FALSE(scene.segment_valid(Vec3(5, 5, 5), Vec3(5, 5, 11)));
  EXPECT_TRUE(scene.point_valid(Vec3(0, 0, 10)));  // the box is closed
}

TEST(CollisionChecker, ZeroLengthSegmentIsAPointCheck) {
  const Scene scene = single_triangle_scene({Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(0, 1, 0)}, 0.5);
  EXPECT_TRUE(scene.segment_valid(Vec3(0, 0, 1), Vec3(0, 0, 1)));
  EXPECT_FALSE(scene.segment_valid(Vec3(0, 0, 0.4), Vec3(0, 0, 0.4)));
}

TEST(CollisionChecker, ConcurrentQueriesGiveTheSameAnswers) {
  const Scene& scene = test::shared_scene("radio_tower");
  scene_files::Rng rng(5);
  const auto segments = test::mixed_query_segments(scene, rng, 4000);
  std::vector<char> serial(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) serial[i] = scene.segment_valid(segments[i].a, segments[i].b);
  std::vector<char> parallel(segments.size());
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      for (std::size_t i = static_cast<std::size_t>(t); i < segments.size(); i += 4) {
        parallel[i] = scene.segment_valid(segments[i].a, segments[i].b);
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
}

}  // namespace
}  // namespace ispars::planning
