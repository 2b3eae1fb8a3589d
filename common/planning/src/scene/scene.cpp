#include "ispars/planning/scene/scene.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/procedural.hpp"
#include "ispars/scene_files/scene_file.hpp"

namespace ispars::planning {

Scene Scene::load(const std::filesystem::path& yaml_path) { return build(scene_files::parse_scene_config(yaml_path)); }

Scene Scene::with_roadmap_parameters(double dense_delta, double sparse_delta, double stretch,
                                     const std::string& source) const {
  scene_files::SceneConfig config = *config_;
  config.source = source;
  config.dense_delta = dense_delta;
  config.sparse_delta = sparse_delta;
  config.stretch = stretch;
  scene_files::check_scene_config(config);
  config.source = config_->source;
  Scene copy = *this;
  copy.config_ = std::make_shared<const scene_files::SceneConfig>(std::move(config));
  return copy;
}

Scene Scene::with_more_pois(std::span<const Vec3> more) const {
  std::vector<Vec3> pois = visibility_->pois();
  pois.insert(pois.end(), more.begin(), more.end());
  Scene copy = *this;
  copy.visibility_ = std::make_shared<const VisibilityOracle>(embree_, std::move(pois), config_->sensor_range);
  return copy;
}

Scene Scene::build(const scene_files::SceneConfig& config) {
  scene_files::check_scene_config(config);
  return build(config, scene_files::scene_mesh(config));
}

Scene Scene::build(const scene_files::SceneConfig& config, scene_files::TriangleMesh mesh) {
  scene_files::SceneFile file =
      scene_files::scene_file_from(config, std::move(mesh));  // the mesh scaled, the POIs made
  std::vector<Vec3> pois = std::move(file.pois);
  mesh = std::move(file.mesh);

  Scene scene;
  scene.config_ = std::make_shared<const scene_files::SceneConfig>(config);
  scene.mesh_ = std::make_shared<const scene_files::TriangleMesh>(std::move(mesh));
  scene.embree_ = std::make_shared<const EmbreeScene>(*scene.mesh_);
  scene.collision_ = std::make_shared<const CollisionChecker>(scene.embree_, config.bounds, config.robot_radius);
  scene.visibility_ = std::make_shared<const VisibilityOracle>(scene.embree_, std::move(pois), config.sensor_range);

  const double distance = scene.collision_->distance_to_surface(config.root);
  if (!(distance > config.robot_radius)) {
    throw params::InputError(
        config.source, "root",
        fmt::format("[{}, {}, {}] is in collision: {:.3f} m from the mesh, robot_radius {}", config.root.x(),
                    config.root.y(), config.root.z(), distance, config.robot_radius));
  }
  return scene;
}

Vec3 Scene::sample_valid_configuration(scene_files::Rng& rng, int max_attempts) const {
  for (int i = 0; i < max_attempts; ++i) {
    const Vec3 q = rng.uniform_in(config_->bounds);
    if (collision_->point_valid(q)) return q;
  }
  throw std::runtime_error(fmt::format("no valid configuration in {} samples of the bounds", max_attempts));
}

}  // namespace ispars::planning
