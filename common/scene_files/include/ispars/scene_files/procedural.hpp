#pragma once
// Seeded procedural structures for tests and demos: a truss bridge, a tank-on-legs tower and a
// city grid, each with a scene configuration whose parameters suit its scale.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ispars/scene_files/scene_config.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::scene_files {

/// The generator names: "truss_bridge", "tank_tower", "city_grid".
[[nodiscard]] const std::vector<std::string>& procedural_kinds();
[[nodiscard]] bool is_procedural_kind(std::string_view kind);
/// The kinds joined by ", ", for error messages.
[[nodiscard]] std::string procedural_kinds_list();

/// The structure of `kind` for `seed`; the same seed gives the same mesh on every machine.
/// Throws std::invalid_argument for an unknown kind.
[[nodiscard]] TriangleMesh make_procedural_mesh(std::string_view kind, std::uint64_t seed);

/// A complete scene configuration for the structure (bounds, radii, root, POIs), with
/// `procedural` set; Scene::build(config) generates the mesh.
[[nodiscard]] SceneConfig procedural_scene_config(std::string_view kind, std::uint64_t seed);

// Building blocks, exposed for tests of their own.
/// An axis-aligned closed box (12 triangles).
void add_box(TriangleMesh& mesh, const Vec3& centre, const Vec3& half_extent);
/// A closed square prism of half-width `half_width` from a to b (12 triangles).
void add_beam(TriangleMesh& mesh, const Vec3& a, const Vec3& b, double half_width);
/// A closed vertical cylinder (4 * sides triangles) standing on `base`.
void add_cylinder(TriangleMesh& mesh, const Vec3& base, double radius, double height, int sides);

}  // namespace ispars::scene_files
