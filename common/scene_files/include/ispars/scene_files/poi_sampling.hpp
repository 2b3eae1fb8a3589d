#pragma once
// Points of interest: sampled on the surface, or read from a file.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::scene_files {

/// True for a triangle lying in the ground plane: all three corners within 0.05 m of the
/// mesh's lowest z and a normal within about 8 degrees of vertical. No aerial sensor sees these.
[[nodiscard]] bool is_ground_triangle(const TriangleMesh& mesh, std::size_t t, double ground_z);

/// `count` points uniform by area on the mesh surface (optionally skipping ground triangles),
/// from `seed` alone: the same points, bit for bit, on every machine.
/// Throws std::invalid_argument when no triangle with positive area is eligible.
[[nodiscard]] std::vector<Vec3> sample_pois_on_surface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed,
                                                       bool skip_ground);

/// Reads POIs from a text file, one "x y z" per line; blank lines and '#' comments are skipped.
/// Throws InputError naming the file, `field` and the line at fault.
[[nodiscard]] std::vector<Vec3> read_poi_file(const std::filesystem::path& path,
                                              const std::string& field = "pois.file");

}  // namespace ispars::scene_files
