#include "ispars/scene_files/poi_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::scene_files {

bool is_ground_triangle(const TriangleMesh& mesh, std::size_t t, double ground_z) {
  const Vec3 a = mesh.corner(t, 0);
  const Vec3 b = mesh.corner(t, 1);
  const Vec3 c = mesh.corner(t, 2);
  for (const Vec3* p : {&a, &b, &c}) {
    if (p->z() - ground_z > 0.05) return false;
  }
  const Vec3 n = (b - a).cross(c - a);
  const double norm = n.norm();
  return norm > 0.0 && std::abs(n.z()) / norm > 0.99;
}

std::vector<Vec3> sample_pois_on_surface(const TriangleMesh& mesh, std::size_t count, std::uint64_t seed,
                                         bool skip_ground) {
  const double ground_z = mesh.bounds().min.z();
  std::vector<double> cumulative;
  std::vector<std::size_t> eligible;
  cumulative.reserve(mesh.triangle_count());
  double total = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (skip_ground && is_ground_triangle(mesh, t, ground_z)) continue;
    const double area =
        0.5 * (mesh.corner(t, 1) - mesh.corner(t, 0)).cross(mesh.corner(t, 2) - mesh.corner(t, 0)).norm();
    if (!(area > 0.0)) continue;
    total += area;
    cumulative.push_back(total);
    eligible.push_back(t);
  }
  if (eligible.empty()) throw std::invalid_argument("no triangle with positive area to sample POIs on");

  Rng rng(seed);
  std::vector<Vec3> pois;
  pois.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double u = rng.uniform01() * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), eligible.size() - 1);
    const std::size_t t = eligible[k];
    // Uniform on the triangle: the square-root warp of two uniforms.
    const double r1 = std::sqrt(rng.uniform01());
    const double r2 = rng.uniform01();
    pois.push_back((1.0 - r1) * mesh.corner(t, 0) + r1 * (1.0 - r2) * mesh.corner(t, 1) + r1 * r2 * mesh.corner(t, 2));
  }
  return pois;
}

std::vector<Vec3> read_poi_file(const std::filesystem::path& path, const std::string& field) {
  std::ifstream in(path);
  if (!in) throw params::InputError(path.string(), field, "cannot open POI file");
  std::vector<Vec3> pois;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream fields(line);
    double x = 0;
    double y = 0;
    double z = 0;
    std::string extra;
    if (!(fields >> x >> y >> z) || (fields >> extra) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      throw params::InputError(path.string(), field,
                               "line " + std::to_string(line_number) + ": expected three finite numbers \"x y z\"");
    }
    pois.emplace_back(x, y, z);
  }
  if (pois.empty()) throw params::InputError(path.string(), field, "POI file holds no points");
  return pois;
}

}  // namespace ispars::scene_files
