#pragma once
// A loaded scene: configuration, triangle soup, POIs, and the geometry queries over them.

#include <filesystem>
#include <memory>
#include <span>
#include <vector>

#include "ispars/planning/geometry/check_counters.hpp"
#include "ispars/planning/geometry/collision_checker.hpp"
#include "ispars/planning/geometry/visibility.hpp"
#include "ispars/scene_files/random.hpp"
#include "ispars/scene_files/scene_config.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::planning {

/// Everything a planner needs about one inspection scene. Immutable after construction and
/// cheap to copy (the heavy parts are shared); every query is const and thread-safe.
class Scene {
 public:
  /// Loads a scene file: parses the YAML, loads (or generates) the mesh, applies the scale,
  /// makes the POIs, builds the BVHs and checks the root. Throws InputError naming the file and
  /// field on any bad input (missing or empty mesh, root in collision, ...).
  [[nodiscard]] static Scene load(const std::filesystem::path& yaml_path);
  /// Builds a scene from a configuration, generating the mesh of a procedural config or loading
  /// its mesh file. Same checks and errors as load().
  [[nodiscard]] static Scene build(const scene_files::SceneConfig& config);
  /// Builds a scene from a configuration and a mesh in memory (config.mesh is not read).
  [[nodiscard]] static Scene build(const scene_files::SceneConfig& config, scene_files::TriangleMesh mesh);

  /// This scene with other roadmap parameters (delta, Delta, t), sharing the geometry. Throws
  /// InputError naming the parameter (as `source`'s field) when one is out of range.
  [[nodiscard]] Scene with_roadmap_parameters(double dense_delta, double sparse_delta, double stretch,
                                              const std::string& source) const;

  /// This scene with `more` POIs after its own (ids pois().size(), ...), sharing the geometry: the
  /// scene an inspection task is planned in. Each POI's visibility is the same as in a scene
  /// whose POIs were all there from the start.
  [[nodiscard]] Scene with_more_pois(std::span<const Vec3> more) const;

  [[nodiscard]] const scene_files::SceneConfig& config() const { return *config_; }
  [[nodiscard]] const scene_files::TriangleMesh& mesh() const { return *mesh_; }
  [[nodiscard]] const std::vector<Vec3>& pois() const { return visibility_->pois(); }
  [[nodiscard]] const CollisionChecker& collision() const { return *collision_; }
  [[nodiscard]] const VisibilityOracle& visibility() const { return *visibility_; }
  [[nodiscard]] const EmbreeScene& embree() const { return *embree_; }

  /// Shorthands for the three queries of the paper.
  [[nodiscard]] bool point_valid(const Vec3& q) const { return collision_->point_valid(q); }
  [[nodiscard]] bool segment_valid(const Vec3& a, const Vec3& b) const { return collision_->segment_valid(a, b); }
  void visible_pois(const Vec3& q, std::vector<PoiId>& out) const { visibility_->visible_pois(q, out); }

  /// A uniform sample of the sampling box that passes the point check, drawn from rng (at most
  /// `max_attempts` draws; throws std::runtime_error when none is valid).
  [[nodiscard]] Vec3 sample_valid_configuration(scene_files::Rng& rng, int max_attempts = 1'000'000) const;

  /// All checks made through this scene so far, by every thread.
  [[nodiscard]] CheckCounts counts() const { return collision_->counts() + visibility_->counts(); }

 private:
  Scene() = default;
  std::shared_ptr<const scene_files::SceneConfig> config_;
  std::shared_ptr<const scene_files::TriangleMesh> mesh_;
  std::shared_ptr<const EmbreeScene> embree_;
  std::shared_ptr<const CollisionChecker> collision_;
  std::shared_ptr<const VisibilityOracle> visibility_;
};

}  // namespace ispars::planning
