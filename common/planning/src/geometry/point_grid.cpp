#include "ispars/planning/geometry/point_grid.hpp"

#include <algorithm>
#include <cmath>

namespace ispars::planning {

PointGrid::Key PointGrid::key(std::int64_t x, std::int64_t y, std::int64_t z) {
  // 21 bits per axis (two's complement, masked): about a million cells each way.
  const auto m = [](std::int64_t v) { return static_cast<std::uint64_t>(v) & 0x1FFFFFULL; };
  return (m(x) << 42) | (m(y) << 21) | m(z);
}

std::int64_t PointGrid::coord(double v) const { return static_cast<std::int64_t>(std::floor(v / cell_)); }

void PointGrid::insert(std::uint32_t id, const Vec3& p) {
  cells_[key(coord(p.x()), coord(p.y()), coord(p.z()))].push_back(id);
}

void PointGrid::within(const Vec3& q, double radius, std::span<const Vec3> positions,
                       std::vector<std::pair<double, std::uint32_t>>& out) const {
  out.clear();
  const double r2 = radius * radius;
  const std::int64_t x0 = coord(q.x() - radius), x1 = coord(q.x() + radius);
  const std::int64_t y0 = coord(q.y() - radius), y1 = coord(q.y() + radius);
  const std::int64_t z0 = coord(q.z() - radius), z1 = coord(q.z() + radius);
  for (std::int64_t x = x0; x <= x1; ++x) {
    for (std::int64_t y = y0; y <= y1; ++y) {
      for (std::int64_t z = z0; z <= z1; ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (const std::uint32_t id : it->second) {
          const double d2 = (positions[id] - q).squaredNorm();
          if (d2 <= r2) out.emplace_back(std::sqrt(d2), id);
        }
      }
    }
  }
  std::sort(out.begin(), out.end());
}

}  // namespace ispars::planning
