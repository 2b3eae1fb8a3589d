// Loading meshes through assimp: formats, node transforms flattened, and named failures.

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/procedural.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"
#include "support/test_support.hpp"

namespace ispars::scene_files {
namespace {

void expect_mesh_error(const std::filesystem::path& path, const std::string& fragment) {
  try {
    (void)load_triangle_mesh(path);
    ADD_FAILURE() << "loaded " << path;
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.file(), path.string());
    EXPECT_EQ(e.field(), "mesh");
    EXPECT_NE(e.problem().find(fragment), std::string::npos) << e.what();
  }
}

TEST(TriangleMesh, ObjRoundTrip) {
  const test::TempDir dir;
  const TriangleMesh original = make_procedural_mesh("tank_tower", 1);
  std::ostringstream obj;
  write_obj(original, obj);
  const TriangleMesh loaded = load_triangle_mesh(dir.write("m.obj", obj.str()));
  EXPECT_EQ(loaded.triangle_count(), original.triangle_count());
  EXPECT_NEAR(loaded.surface_area(), original.surface_area(), 1e-6 * original.surface_area());
  EXPECT_TRUE(loaded.bounds().min.isApprox(original.bounds().min, 1e-6));
}

TEST(TriangleMesh, QuadsAreTriangulatedAndStlLoads) {
  const test::TempDir dir;
  const auto quad = load_triangle_mesh(dir.write("q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"));
  EXPECT_EQ(quad.triangle_count(), 2u);
  EXPECT_DOUBLE_EQ(quad.surface_area(), 1.0);
  const auto stl = load_triangle_mesh(dir.write("t.stl",
                                                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 2 0 "
                                                "0\nvertex 0 2 0\nendloop\nendfacet\nendsolid t\n"));
  EXPECT_EQ(stl.triangle_count(), 1u);
  EXPECT_DOUBLE_EQ(stl.surface_area(), 2.0);
}

TEST(TriangleMesh, NodeTransformsAreFlattenedIntoWorldCoordinates) {
  // A glTF scene: one triangle mesh instanced by two nodes, one translated by (10, 0, 0) under a
  // parent scaled by 2. World vertices must carry both transforms.
  const test::TempDir dir;
  // Buffer: 3 float vertices (0,0,0) (1,0,0) (0,1,0) then 3 uint16 indices 0 1 2 (+2 pad bytes).
  const std::string buffer_b64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIAAAA=";
  const std::string gltf = R"({
    "asset": {"version": "2.0"},
    "scene": 0,
    "scenes": [{"nodes": [0, 1]}],
    "nodes": [{"mesh": 0}, {"scale": [2, 2, 2], "children": [2]}, {"mesh": 0, "translation": [10, 0, 0]}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
    "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)" +
                           buffer_b64 + R"("}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
    "accessors": [
      {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
  })";
  const TriangleMesh mesh = load_triangle_mesh(dir.write("two.gltf", gltf));
  ASSERT_EQ(mesh.triangle_count(), 2u);
  const Aabb box = mesh.bounds();
  EXPECT_NEAR(box.min.x(), 0.0, 1e-6);
  EXPECT_NEAR(box.max.x(), 22.0, 1e-5);  // 2 * (10 + 1)
  EXPECT_NEAR(mesh.surface_area(), 0.5 + 0.5 * 4, 1e-5);
}

TEST(TriangleMesh, BadFilesAreNamed) {
  const test::TempDir dir;
  expect_mesh_error(dir.path() / "missing.obj", "does not exist");
  expect_mesh_error(dir.path(), "directory");
  expect_mesh_error(dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "");
  expect_mesh_error(dir.write("garbage.stl", std::string("\x01\x02 this is no mesh \x7f", 21)), "");
  expect_mesh_error(dir.write("empty.obj", ""), "");
  expect_mesh_error(dir.write("unknown.xyz123", "hello"), "cannot read mesh");
}

TEST(TriangleMesh, ScaleAndAppend) {
  TriangleMesh a;
  add_box(a, Vec3(0, 0, 0), Vec3(1, 1, 1));
  TriangleMesh b = a;
  b.scale(2.0);
  EXPECT_NEAR(b.surface_area(), 4 * a.surface_area(), 1e-9);
  a.append(b);
  EXPECT_EQ(a.triangle_count(), 24u);
  EXPECT_EQ(a.triangles.back()[0], a.triangles[11][0] + 8);
}

}  // namespace
}  // namespace ispars::scene_files
