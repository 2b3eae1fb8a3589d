#include "ispars/planning/scene/scene_fingerprint.hpp"

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace ispars::planning {
namespace {

class Fnv1a {
 public:
  void bytes(const void* data, std::size_t size) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ull;
    }
  }
  void number(double v) { bytes(&v, sizeof v); }
  void vec(const Vec3& v) {
    number(v.x());
    number(v.y());
    number(v.z());
  }
  [[nodiscard]] std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

std::string scene_fingerprint(const Scene& scene) {
  Fnv1a h;
  const scene_files::TriangleMesh& mesh = scene.mesh();
  const std::uint64_t nv = mesh.vertices.size(), nt = mesh.triangles.size(), np = scene.pois().size();
  h.bytes(&nv, sizeof nv);
  for (const auto& v : mesh.vertices) h.bytes(v.data(), 3 * sizeof(float));
  h.bytes(&nt, sizeof nt);
  for (const auto& t : mesh.triangles) h.bytes(t.data(), sizeof t);
  h.bytes(&np, sizeof np);
  for (const Vec3& p : scene.pois()) h.vec(p);
  const scene_files::SceneConfig& c = scene.config();
  h.vec(c.bounds.min);
  h.vec(c.bounds.max);
  for (const double v : {c.scale, c.robot_radius, c.sensor_range, c.dense_delta, c.sparse_delta, c.stretch})
    h.number(v);
  h.vec(c.root);
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h.value()));
  return text;
}

}  // namespace ispars::planning
