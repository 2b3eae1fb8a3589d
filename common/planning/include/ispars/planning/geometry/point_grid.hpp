#pragma once
// A uniform hash grid over a growing point set, for fixed-radius neighbour queries.

#include <cstdint>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// Points by cell of side `cell`; a radius query visits only the cells its ball touches.
/// Results come sorted by (distance, id), so every caller sees one deterministic order.
class PointGrid {
 public:
  explicit PointGrid(double cell) : cell_(cell) {}

  /// Registers point `id` at p (ids index the caller's position array).
  void insert(std::uint32_t id, const Vec3& p);
  /// Replaces `out` with (distance, id) of every point within `radius` of q (<= radius),
  /// nearest first, ties by id. `positions[id]` must be the inserted points.
  void within(const Vec3& q, double radius, std::span<const Vec3> positions,
              std::vector<std::pair<double, std::uint32_t>>& out) const;

 private:
  using Key = std::uint64_t;
  [[nodiscard]] static Key key(std::int64_t x, std::int64_t y, std::int64_t z);
  [[nodiscard]] std::int64_t coord(double v) const;

  double cell_;
  std::unordered_map<Key, std::vector<std::uint32_t>> cells_;
};

}  // namespace ispars::planning
