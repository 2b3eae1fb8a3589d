#pragma once
// The scene file: a YAML contract other tools and tests rely on.
//
//   mesh: water_tower.obj            # path relative to this YAML file
//   scale: 1.0                       # optional, uniform, about the origin
//   bounds: {min: [-15, -15, 0.5], max: [15, 15, 30]}   # sampling box for the robot's centre
//   robot_radius: 0.5
//   sensor_range: 6
//   dense_delta: 2.0                 # delta: dense connection radius
//   sparse_delta: 3.0                # Delta: sparse visibility radius
//   stretch: 1.05                    # t
//   root: [10, 0, 2]                 # departure configuration
//   pois: {count: 300, seed: 7}      # or {file: pois.txt}, one "x y z" per line
//
// Extensions: `name:` (defaults to the file's stem), `pois.skip_ground: true` (do not sample
// POIs on triangles lying in the ground plane), and `procedural: {kind: K, seed: S}` in place
// of `mesh:` for the generated scenes of procedural.hpp (then every other field is optional and
// defaults to the generator's own parameters).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "ispars/params/spec.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::scene_files {

/// Where the POIs come from: `count` sampled on the surface from `seed`, or a file.
struct PoiSource {
  std::size_t count = 0;
  std::uint64_t seed = 0;
  bool skip_ground = false;
  std::filesystem::path file;  ///< Non-empty when the POIs are read from a file.
};

/// A generated mesh in place of a file: one of procedural_kinds(), with a seed.
struct ProceduralSource {
  std::string kind;
  std::uint64_t seed = 0;
};

/// A scene's own numbers, declared once (its roadmap parameters, dense_delta, sparse_delta and
/// stretch, are the recipe's: roadmap_parameters.hpp). Scene units; a mesh 1000 km across is not
/// a scene.
inline constexpr params::Spec<double> kScale{"scale", 0.0, 1e6, "uniform scale of the mesh, about the origin",
                                             params::Lower::open};
inline constexpr params::Spec<double> kRobotRadius{"robot_radius", 0.0, 1e6, "the robot's radius (a sphere)",
                                                   params::Lower::open};
inline constexpr params::Spec<double> kSensorRange{"sensor_range", 0.0, 1e6, "how far the sensor sees",
                                                   params::Lower::open};

/// A parsed and checked scene file. Every number is finite and in its valid range.
struct SceneConfig {
  std::string source;          ///< The YAML file it came from (for error messages).
  std::string name;            ///< A short name for reports.
  std::filesystem::path mesh;  ///< Resolved mesh path; empty when procedural.
  std::optional<ProceduralSource> procedural;
  double scale = 1.0;
  Aabb bounds;
  double robot_radius = 0.0;
  double sensor_range = 0.0;
  double dense_delta = 0.0;   ///< delta
  double sparse_delta = 0.0;  ///< Delta
  double stretch = 0.0;       ///< t
  Vec3 root = Vec3::Zero();
  PoiSource pois;

  /// Its numbers, each with its declaration: every one a mesh scene must give, scale aside.
  static void describe(auto& self, auto&& field) {
    field(kScale, self.scale);
    field(kRobotRadius, self.robot_radius);
    field(kSensorRange, self.sensor_range);
    field(kDenseDelta, self.dense_delta);
    field(kSparseDelta, self.sparse_delta);
    field(kStretch, self.stretch);
  }
};

/// Reads and checks a scene file. Throws InputError naming the file and the field on a
/// missing, malformed, non-finite or out-of-range value, an unknown field, or a YAML syntax
/// error (field "yaml", with line and column). The mesh itself is not loaded here.
[[nodiscard]] SceneConfig parse_scene_config(const std::filesystem::path& yaml_path);

/// The same from text; relative paths resolve against `base_dir`, errors name `source`.
[[nodiscard]] SceneConfig parse_scene_config_text(std::string_view text, const std::filesystem::path& base_dir,
                                                  const std::string& source);

/// Checks the numeric invariants of a config built in code (the parser calls it too).
/// Throws InputError naming config.source and the field.
void check_scene_config(const SceneConfig& config);

}  // namespace ispars::scene_files
