#include "ispars/scene_files/procedural.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "ispars/scene_files/random.hpp"

namespace ispars::scene_files {
namespace {

std::uint32_t add_vertex(TriangleMesh& mesh, const Vec3& p) {
  mesh.vertices.push_back(p.cast<float>());
  return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
}

// Eight corners c[i] with bit 0 = +u, bit 1 = +v, bit 2 = +w; emits the 12 faces.
void add_hexahedron(TriangleMesh& mesh, const std::array<Vec3, 8>& c) {
  std::array<std::uint32_t, 8> id{};
  for (std::size_t i = 0; i < 8; ++i) id[i] = add_vertex(mesh, c[i]);
  static constexpr std::array<std::array<int, 4>, 6> kFaces{
      {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}}};
  for (const auto& f : kFaces) {
    const auto at = [&](int k) { return id[static_cast<std::size_t>(f[static_cast<std::size_t>(k)])]; };
    mesh.triangles.push_back({at(0), at(1), at(2)});
    mesh.triangles.push_back({at(0), at(2), at(3)});
  }
}

TriangleMesh truss_bridge(std::uint64_t seed) {
  Rng rng(seed);
  const int panels = 6 + static_cast<int>(rng.below(3));
  const double panel = 2.0 + rng.uniform(0.0, 0.5);
  const double span = panels * panel;
  const double half_width = 3.0;
  const double height = 3.5 + rng.uniform(0.0, 1.0);
  const double beam = 0.1;
  TriangleMesh mesh;
  add_box(mesh, {0, 0, 0}, {span / 2 + 1.0, half_width + 0.3, 0.3});  // deck
  for (const double y : {-half_width, half_width}) {
    add_beam(mesh, {-span / 2, y, height}, {span / 2, y, height}, beam);  // top chord
    for (int i = 0; i <= panels; ++i) {
      const double x = -span / 2 + i * panel;
      add_beam(mesh, {x, y, 0.3}, {x, y, height}, beam);  // vertical
      if (i < panels) {
        const double next = x + panel;
        const bool rising = i < panels / 2;
        add_beam(mesh, {rising ? x : next, y, 0.3}, {rising ? next : x, y, height}, beam * 0.7);
      }
    }
  }
  for (int i = 0; i <= panels; i += 2) {  // top lateral bracing
    const double x = -span / 2 + i * panel;
    add_beam(mesh, {x, -half_width, height}, {x, half_width, height}, beam * 0.7);
  }
  return mesh;
}

TriangleMesh tank_tower(std::uint64_t seed) {
  Rng rng(seed);
  const double height = 12.0 + rng.uniform(0.0, 4.0);
  const double foot = 2.5;
  const double top = 1.6;
  const double tank_radius = 2.6 + rng.uniform(0.0, 0.6);
  TriangleMesh mesh;
  const std::array<Vec3, 4> dirs{Vec3(1, 1, 0), Vec3(-1, 1, 0), Vec3(-1, -1, 0), Vec3(1, -1, 0)};
  const auto leg_at = [&](const Vec3& d, double z) {
    const double s = foot + (top - foot) * (z / height);
    return Vec3(d.x() * s, d.y() * s, z);
  };
  for (const auto& d : dirs) add_beam(mesh, leg_at(d, 0.0), leg_at(d, height), 0.15);
  const int levels = 3;
  for (int l = 1; l <= levels; ++l) {
    const double z0 = height * (l - 1) / levels;
    const double z1 = height * l / levels;
    for (std::size_t k = 0; k < 4; ++k) {
      const Vec3& d0 = dirs[k];
      const Vec3& d1 = dirs[(k + 1) % 4];
      add_beam(mesh, leg_at(d0, z1), leg_at(d1, z1), 0.08);  // ring brace
      add_beam(mesh, leg_at(d0, z0), leg_at(d1, z1), 0.03);  // thin diagonal wire
    }
  }
  add_cylinder(mesh, {0, 0, height}, tank_radius, 4.0 + rng.uniform(0.0, 1.0), 24);
  return mesh;
}

TriangleMesh city_grid(std::uint64_t seed) {
  Rng rng(seed);
  const int blocks = 4;
  const double pitch = 20.0;
  TriangleMesh mesh;
  for (int i = 0; i < blocks; ++i) {
    for (int j = 0; j < blocks; ++j) {
      const double cx = (i - (blocks - 1) / 2.0) * pitch + rng.uniform(-1.5, 1.5);
      const double cy = (j - (blocks - 1) / 2.0) * pitch + rng.uniform(-1.5, 1.5);
      const double hx = rng.uniform(4.0, 7.0);
      const double hy = rng.uniform(4.0, 7.0);
      const double h = rng.uniform(5.0, 25.0);
      add_box(mesh, {cx, cy, h / 2}, {hx, hy, h / 2});
    }
  }
  return mesh;
}

}  // namespace

void add_box(TriangleMesh& mesh, const Vec3& centre, const Vec3& half_extent) {
  std::array<Vec3, 8> c;
  for (std::size_t i = 0; i < 8; ++i) {
    c[i] = centre + Vec3((i & 1) ? half_extent.x() : -half_extent.x(), (i & 2) ? half_extent.y() : -half_extent.y(),
                         (i & 4) ? half_extent.z() : -half_extent.z());
  }
  add_hexahedron(mesh, c);
}

void add_beam(TriangleMesh& mesh, const Vec3& a, const Vec3& b, double half_width) {
  const Vec3 axis = (b - a).normalized();
  const Vec3 helper = std::abs(axis.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
  const Vec3 u = axis.cross(helper).normalized() * half_width;
  const Vec3 v = axis.cross(u).normalized() * half_width;
  std::array<Vec3, 8> c;
  for (std::size_t i = 0; i < 8; ++i) {
    c[i] = ((i & 4) ? b : a) + ((i & 1) ? u : Vec3(-u)) + ((i & 2) ? v : Vec3(-v));
  }
  add_hexahedron(mesh, c);
}

void add_cylinder(TriangleMesh& mesh, const Vec3& base, double radius, double height, int sides) {
  const std::uint32_t bottom_centre = add_vertex(mesh, base);
  const std::uint32_t top_centre = add_vertex(mesh, base + Vec3(0, 0, height));
  const std::uint32_t first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int k = 0; k < sides; ++k) {
    // Angles from an exact rational turn keep the mesh identical wherever cos/sin round alike.
    const double angle = 2.0 * M_PI * k / sides;
    const Vec3 rim = base + Vec3(radius * std::cos(angle), radius * std::sin(angle), 0.0);
    add_vertex(mesh, rim);
    add_vertex(mesh, rim + Vec3(0, 0, height));
  }
  const auto n = static_cast<std::uint32_t>(sides);
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t b0 = first + 2 * k;
    const std::uint32_t t0 = b0 + 1;
    const std::uint32_t b1 = first + 2 * ((k + 1) % n);
    const std::uint32_t t1 = b1 + 1;
    mesh.triangles.push_back({b0, b1, t1});
    mesh.triangles.push_back({b0, t1, t0});
    mesh.triangles.push_back({bottom_centre, b1, b0});
    mesh.triangles.push_back({top_centre, t0, t1});
  }
}

const std::vector<std::string>& procedural_kinds() {
  static const std::vector<std::string> kinds{"truss_bridge", "tank_tower", "city_grid"};
  return kinds;
}

bool is_procedural_kind(std::string_view kind) {
  for (const auto& k : procedural_kinds()) {
    if (k == kind) return true;
  }
  return false;
}

std::string procedural_kinds_list() {
  std::string list;
  for (const auto& k : procedural_kinds()) list += (list.empty() ? "" : ", ") + k;
  return list;
}

TriangleMesh make_procedural_mesh(std::string_view kind, std::uint64_t seed) {
  if (kind == "truss_bridge") return truss_bridge(seed);
  if (kind == "tank_tower") return tank_tower(seed);
  if (kind == "city_grid") return city_grid(seed);
  throw std::invalid_argument("unknown procedural kind '" + std::string(kind) + "' (known: " + procedural_kinds_list() +
                              ")");
}

SceneConfig procedural_scene_config(std::string_view kind, std::uint64_t seed) {
  if (!is_procedural_kind(kind)) {
    throw std::invalid_argument("unknown procedural kind '" + std::string(kind) + "'");
  }
  SceneConfig c;
  c.source = "procedural:" + std::string(kind);
  c.name = std::string(kind) + "_" + std::to_string(seed);
  c.procedural = ProceduralSource{std::string(kind), seed};
  c.stretch = 1.05;
  c.pois = PoiSource{200, seed, false, {}};
  if (kind == "truss_bridge") {
    c.bounds = {Vec3(-14, -9, -4), Vec3(14, 9, 8)};
    c.robot_radius = 0.3;
    c.sensor_range = 4.0;
    c.dense_delta = 1.0;
    c.root = Vec3(-13, 0, 1.5);
  } else if (kind == "tank_tower") {
    c.bounds = {Vec3(-12, -12, 0.5), Vec3(12, 12, 26)};
    c.robot_radius = 0.5;
    c.sensor_range = 6.0;
    c.dense_delta = 2.0;
    c.root = Vec3(9, 0, 2);
    c.pois.skip_ground = true;
  } else {
    c.bounds = {Vec3(-50, -50, 1), Vec3(50, 50, 32)};
    c.robot_radius = 0.8;
    c.sensor_range = 10.0;
    c.dense_delta = 4.5;
    c.root = Vec3(0, -48, 3);
    c.pois.skip_ground = true;
  }
  c.sparse_delta = 1.5 * c.dense_delta;
  return c;
}

}  // namespace ispars::scene_files
