#pragma once
// A scene file read without the planning geometry: its config, its mesh (loaded with assimp or
// generated, then scaled) and its points of interest (read, or sampled on the mesh surface), as
// Scene::build makes them before it builds its collision and visibility checks. For programs
// that show a scene but never plan on it (the live viewer's gateway).

#include <filesystem>
#include <vector>

#include "ispars/scene_files/scene_config.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::scene_files {

/// A scene file's contents: what it says, its mesh and its POIs.
struct SceneFile {
  SceneConfig config;
  TriangleMesh mesh;
  std::vector<Vec3> pois;
};

/// Reads and checks `yaml_path`, loads or generates its mesh and makes its POIs. Throws
/// InputError naming the file and the field.
[[nodiscard]] SceneFile read_scene_file(const std::filesystem::path& yaml_path);

/// The mesh `config` names: loaded with assimp, or generated for a procedural scene (not scaled).
[[nodiscard]] TriangleMesh scene_mesh(const SceneConfig& config);

/// The mesh scaled by `config` and the POIs it names (InputError for an empty mesh, a bad POI file
/// or a POI count the surface cannot give).
[[nodiscard]] SceneFile scene_file_from(const SceneConfig& config, TriangleMesh mesh);

}  // namespace ispars::scene_files
