#pragma once
// A triangle soup in world coordinates, and loading one from any mesh format assimp reads.

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ispars/roadmap/vec.hpp"

namespace ispars::scene_files {

/// An indexed triangle soup in world coordinates (metres). No winding, normal sign or
/// watertightness is assumed: the obstacle is the union of the triangles themselves.
/// Vertices are single precision, as the ray tracer stores them; every exact test reads these
/// same values as doubles, so the fast and the reference geometry see one identical surface.
struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;

  [[nodiscard]] std::size_t triangle_count() const { return triangles.size(); }
  [[nodiscard]] bool empty() const { return triangles.empty(); }
  /// Corner k (0, 1, 2) of triangle t, in double precision.
  [[nodiscard]] Vec3 corner(std::size_t t, int k) const {
    return vertices[triangles[t][static_cast<std::size_t>(k)]].cast<double>();
  }
  /// Bounding box of all vertices referenced by a triangle (zero box for an empty mesh).
  [[nodiscard]] Aabb bounds() const;
  /// Sum of the triangle areas.
  [[nodiscard]] double surface_area() const;
  /// Appends another mesh's triangles.
  void append(const TriangleMesh& other);
  /// Scales every vertex about the origin.
  void scale(double factor);
};

/// Loads every mesh of a file (obj, stl, ply, dae, gltf/glb, off, ...) through assimp and
/// flattens all meshes and node transforms into one world-space triangle soup. Points and
/// lines are dropped; zero-area triangles are kept (they are still obstacles).
/// Throws InputError naming the file and `field` when the file is missing, unreadable,
/// malformed, holds no triangles, or holds a non-finite coordinate.
TriangleMesh load_triangle_mesh(const std::filesystem::path& path, const std::string& field = "mesh");

/// Writes the mesh as a Wavefront OBJ (vertices and faces only).
void write_obj(const TriangleMesh& mesh, std::ostream& out);

}  // namespace ispars::scene_files
