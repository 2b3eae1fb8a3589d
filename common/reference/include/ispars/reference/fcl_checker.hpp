#pragma once
// A second, independent collision checker built on FCL, for cross-checks and benchmarks.

#include <memory>

#include "ispars/roadmap/vec.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::reference {

/// Point and segment validity through FCL's sphere- and capsule-vs-mesh collision (an OBBRSS
/// hierarchy over the same triangles). Same definitions as CollisionChecker: a configuration
/// touching a triangle is in collision; the mesh is a surface, not a solid. Thread-safe.
class FclCollisionChecker {
 public:
  FclCollisionChecker(const scene_files::TriangleMesh& mesh, Aabb bounds, double robot_radius);
  ~FclCollisionChecker();
  FclCollisionChecker(const FclCollisionChecker&) = delete;
  FclCollisionChecker& operator=(const FclCollisionChecker&) = delete;

  [[nodiscard]] bool point_valid(const Vec3& q) const;
  [[nodiscard]] bool segment_valid(const Vec3& a, const Vec3& b) const;

 private:
  struct Model;
  std::unique_ptr<Model> model_;
  Aabb bounds_;
  double radius_;
};

}  // namespace ispars::reference
