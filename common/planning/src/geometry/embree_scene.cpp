#include "ispars/planning/geometry/embree_scene.hpp"

#include <cstring>
#include <stdexcept>
#include <string>

namespace ispars::planning {

std::vector<Triangle> to_triangles(const scene_files::TriangleMesh& mesh) {
  std::vector<Triangle> out;
  out.reserve(mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    out.push_back({mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2)});
  }
  return out;
}

namespace {

void throw_on_device_error(RTCDevice device, const char* what) {
  const RTCError error = rtcGetDeviceError(device);
  if (error != RTC_ERROR_NONE) {
    throw std::runtime_error(std::string("Embree error ") + std::to_string(error) + " in " + what);
  }
}

}  // namespace

EmbreeScene::EmbreeScene(const scene_files::TriangleMesh& mesh) : triangles_(to_triangles(mesh)) {
  device_ = rtcNewDevice("verbose=0");
  if (device_ == nullptr) throw std::runtime_error("Embree: cannot create a device");
  scene_ = rtcNewScene(device_);
  // Robust traversal: no rays slip through shared edges, so visibility does not depend on luck.
  // Context filters let the visibility oracle confirm each candidate hit in double precision.
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  throw_on_device_error(device_, "buffer allocation");
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    std::memcpy(vertices + 3 * i, mesh.vertices[i].data(), 3 * sizeof(float));
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k)
      indices[3 * t + static_cast<std::size_t>(k)] = mesh.triangles[t][static_cast<std::size_t>(k)];
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometryByID(scene_, geometry, 0);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(scene_);
  throw_on_device_error(device_, "scene build");
}

EmbreeScene::~EmbreeScene() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

}  // namespace ispars::planning
