#pragma once
// An Embree BVH over a triangle soup, shared by the collision checker and the visibility oracle.

#include <memory>
#include <vector>

#include <embree3/rtcore.h>

#include "ispars/planning/geometry/distance.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::planning {

/// The scene's triangles twice over: an Embree BVH (single precision, for culling and rays) and
/// the same corners in double precision (for the exact tests run on what the BVH returns).
/// Immutable after construction; every query on it is safe from many threads.
class EmbreeScene {
 public:
  explicit EmbreeScene(const scene_files::TriangleMesh& mesh);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// The committed Embree scene, for rtcPointQuery and rtcOccluded calls.
  [[nodiscard]] RTCScene handle() const { return scene_; }
  /// Triangle `id` in double precision (ids are the mesh's triangle indices).
  [[nodiscard]] const Triangle& triangle(unsigned id) const { return triangles_[id]; }
  /// Every triangle in double precision, in mesh order.
  [[nodiscard]] const std::vector<Triangle>& triangles() const { return triangles_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  std::vector<Triangle> triangles_;
};

/// Double-precision copies of a mesh's triangles, in mesh order.
std::vector<Triangle> to_triangles(const scene_files::TriangleMesh& mesh);

}  // namespace ispars::planning
