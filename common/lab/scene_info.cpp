// `ispars-lab scene info`: what a scene holds and how much of it a sensor can see.

#include <fmt/format.h>

#include <iostream>
#include <vector>

#include "commands.hpp"
#include "flags.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "json_output.hpp"
#include "timing.hpp"

namespace ispars::lab {

int run_scene_info(const SceneInfoOptions& options) {
  const double t0 = now_seconds();
  const planning::Scene scene = planning::Scene::load(options.scene);
  const double load_seconds = now_seconds() - t0;
  const scene_files::SceneConfig& config = scene.config();

  const double root_distance = scene.collision().distance_to_surface(config.root);
  const std::vector<PoiId> root_chi = scene.visibility().visible_pois(config.root);

  // POIs seen from at least one of N random valid configurations.
  scene_files::Rng rng(options.seed);
  std::vector<char> seen(scene.pois().size(), 0);
  std::vector<PoiId> chi;
  std::size_t draws = 0;
  const double t1 = now_seconds();
  for (std::size_t i = 0; i < options.samples; ++i) {
    Vec3 q;
    do {
      q = rng.uniform_in(config.bounds);
      ++draws;
    } while (!scene.point_valid(q));
    scene.visible_pois(q, chi);
    for (const PoiId id : chi) seen[id] = 1;
  }
  const double sample_seconds = now_seconds() - t1;
  std::size_t seen_count = 0;
  for (const char s : seen) seen_count += static_cast<std::size_t>(s);
  const double valid_fraction = static_cast<double>(options.samples) / static_cast<double>(draws);

  nlohmann::json out = {
      {"scene", config.name},
      {"file", config.source},
      {"mesh", config.procedural ? "procedural:" + config.procedural->kind : config.mesh.string()},
      {"triangles", scene.mesh().triangle_count()},
      {"mesh_bounds", to_json(scene.mesh().bounds())},
      {"surface_area", scene.mesh().surface_area()},
      {"bounds", to_json(config.bounds)},
      {"robot_radius", config.robot_radius},
      {"sensor_range", config.sensor_range},
      {"dense_delta", config.dense_delta},
      {"sparse_delta", config.sparse_delta},
      {"stretch", config.stretch},
      {"root", to_json(config.root)},
      {"root_clearance", root_distance - config.robot_radius},
      {"root_visible_pois", root_chi.size()},
      {"pois", scene.pois().size()},
      {"samples", options.samples},
      {"seed", options.seed},
      {"valid_fraction", valid_fraction},
      {"pois_seen", seen_count},
      {"load_seconds", load_seconds},
      {"sample_seconds", sample_seconds},
      {"checks", to_json(scene.counts())},
  };
  if (options.json) {
    std::cout << out.dump() << std::endl;
    return 0;
  }
  const Aabb mb = scene.mesh().bounds();
  std::cout << fmt::format(
      "scene         {} ({})\n"
      "mesh          {}: {} triangles, {:.0f} m^2\n"
      "mesh bounds   [{:.2f}, {:.2f}, {:.2f}] .. [{:.2f}, {:.2f}, {:.2f}]\n"
      "sampling box  [{:g}, {:g}, {:g}] .. [{:g}, {:g}, {:g}], {:.1f}% valid\n"
      "robot         radius {:g}, sensor range {:g}, delta {:g}, Delta {:g}, t {:g}\n"
      "root          [{:g}, {:g}, {:g}], clearance {:.3f} m, sees {} POIs\n"
      "POIs          {} ({} seen from {} random valid configurations, {:.1f}%)\n"
      "checks        {} point, {} segment, {} rays\n"
      "time          load {:.3f} s, sampling {:.3f} s\n",
      config.name, config.source, out["mesh"].get<std::string>(), scene.mesh().triangle_count(),
      scene.mesh().surface_area(), mb.min.x(), mb.min.y(), mb.min.z(), mb.max.x(), mb.max.y(), mb.max.z(),
      config.bounds.min.x(), config.bounds.min.y(), config.bounds.min.z(), config.bounds.max.x(), config.bounds.max.y(),
      config.bounds.max.z(), 100.0 * valid_fraction, config.robot_radius, config.sensor_range, config.dense_delta,
      config.sparse_delta, config.stretch, config.root.x(), config.root.y(), config.root.z(),
      root_distance - config.robot_radius, root_chi.size(), scene.pois().size(), seen_count, options.samples,
      100.0 * static_cast<double>(seen_count) / static_cast<double>(scene.pois().size()), scene.counts().point,
      scene.counts().segment, scene.counts().rays, load_seconds, sample_seconds);
  return 0;
}

CLI::App* add_scene_info_command(CLI::App& parent, SceneInfoOptions& options) {
  auto* cmd = parent.add_subcommand(
      "info", "Triangles, bounds, POIs, root clearance and POIs seen from random valid configurations");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  cmd->add_option("--samples", options.samples, "Random valid configurations for the coverage estimate")
      ->check(CLI::Range(std::size_t{1}, std::size_t{10'000'000}));
  cmd->add_option("--seed", options.seed, "Seed of the random configurations");
  return cmd;
}

}  // namespace ispars::lab
