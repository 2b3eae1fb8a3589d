// Procedural structures: deterministic, varied by seed, and consistent with their configs.

#include <gtest/gtest.h>

#include <map>

#include "ispars/planning/scene/scene.hpp"
#include "ispars/scene_files/procedural.hpp"

namespace ispars::scene_files {
namespace {

TEST(Procedural, SameSeedSameMeshOtherSeedOtherMesh) {
  for (const auto& kind : procedural_kinds()) {
    const TriangleMesh a = make_procedural_mesh(kind, 4);
    const TriangleMesh b = make_procedural_mesh(kind, 4);
    const TriangleMesh c = make_procedural_mesh(kind, 5);
    EXPECT_EQ(a.vertices, b.vertices) << kind;
    EXPECT_EQ(a.triangles, b.triangles) << kind;
    EXPECT_NE(a.vertices, c.vertices) << kind;
    EXPECT_GT(a.triangle_count(), 100u) << kind;
  }
}

TEST(Procedural, ScenesBuildWithValidRootsInsideTheirBounds) {
  for (const auto& kind : procedural_kinds()) {
    for (std::uint64_t seed = 0; seed < 8; ++seed) {
      const planning::Scene scene = planning::Scene::build(procedural_scene_config(kind, seed));  // checks the root
      const Aabb mesh_box = scene.mesh().bounds();
      const Aabb& box = scene.config().bounds;
      // The structure fits in the sampling box with room for the robot to fly around it.
      EXPECT_TRUE((mesh_box.min.head<2>().array() > box.min.head<2>().array()).all()) << kind;
      EXPECT_TRUE((mesh_box.max.array() < box.max.array()).all()) << kind;
    }
  }
}

TEST(Procedural, UnknownKindIsRejected) {
  EXPECT_THROW((void)make_procedural_mesh("pyramid", 1), std::invalid_argument);
  EXPECT_THROW((void)procedural_scene_config("pyramid", 1), std::invalid_argument);
}

TEST(Procedural, BoxAndBeamAreClosed) {
  // Every edge of a closed triangulated surface is shared by exactly two triangles.
  TriangleMesh mesh;
  add_box(mesh, Vec3(0, 0, 0), Vec3(1, 2, 3));
  add_beam(mesh, Vec3(0, 0, 0), Vec3(3, 1, 2), 0.1);
  add_cylinder(mesh, Vec3(5, 5, 0), 1.0, 2.0, 12);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      auto a = t[static_cast<std::size_t>(k)];
      auto b = t[static_cast<std::size_t>((k + 1) % 3)];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [edge, count] : edges) EXPECT_EQ(count, 2);
  const TriangleMesh box_only{mesh.vertices, {mesh.triangles.begin(), mesh.triangles.begin() + 12}};
  EXPECT_NEAR(box_only.surface_area(), 2 * (2 * 4 + 2 * 6 + 4 * 6), 1e-4);
}

}  // namespace
}  // namespace ispars::scene_files
