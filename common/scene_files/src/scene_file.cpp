#include "ispars/scene_files/scene_file.hpp"

#include <stdexcept>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/poi_sampling.hpp"
#include "ispars/scene_files/procedural.hpp"

namespace ispars::scene_files {

SceneFile scene_file_from(const SceneConfig& config, TriangleMesh mesh) {
  check_scene_config(config);
  if (mesh.empty()) throw params::InputError(config.source, "mesh", "mesh contains no triangles");
  if (config.scale != 1.0) mesh.scale(config.scale);
  SceneFile file;
  if (!config.pois.file.empty()) {
    file.pois = read_poi_file(config.pois.file, "pois.file");
  } else {
    try {
      file.pois = sample_pois_on_surface(mesh, config.pois.count, config.pois.seed, config.pois.skip_ground);
    } catch (const std::invalid_argument& e) {
      throw params::InputError(config.source, "pois", e.what());
    }
  }
  file.config = config;
  file.mesh = std::move(mesh);
  return file;
}

TriangleMesh scene_mesh(const SceneConfig& config) {
  return config.procedural ? make_procedural_mesh(config.procedural->kind, config.procedural->seed)
                           : load_triangle_mesh(config.mesh, "mesh");
}

SceneFile read_scene_file(const std::filesystem::path& yaml_path) {
  const SceneConfig config = parse_scene_config(yaml_path);
  return scene_file_from(config, scene_mesh(config));
}

}  // namespace ispars::scene_files
