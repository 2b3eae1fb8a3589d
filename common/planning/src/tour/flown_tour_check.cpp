#include "ispars/planning/tour/flown_tour_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ispars::planning {

FlownTourCheck check_flown_tour(const Scene& scene, const Vec3& root, std::span<const PoiId> targets,
                                std::span<const Vec3> stops, double stated_cost) {
  FlownTourCheck c;
  const auto fail = [&c](std::string why) {
    if (c.problem.empty()) c.problem = std::move(why);
  };
  if (stops.empty() || stops.front() != root || stops.back() != root)
    fail("the tour does not start and end at the root");
  for (std::size_t i = 0; i < stops.size(); ++i) {
    const Vec3& q = stops[i];
    if (!scene.config().bounds.contains(q) || !scene.point_valid(q)) {
      fail(fmt::format("stop {} at ({:.4f}, {:.4f}, {:.4f}) is not a valid configuration", i, q.x(), q.y(), q.z()));
    }
  }
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
    if (stops[i + 1] != stops[i] && !scene.segment_valid(stops[i], stops[i + 1])) {
      fail(fmt::format("the segment from stop {} to stop {} is not collision-free", i, i + 1));
    }
  }
  std::vector<char> seen(targets.size(), 0);
  for (const Vec3& q : stops) {
    std::vector<PoiId> mine;
    for (const PoiId p : scene.visibility().visible_pois(q)) {
      const auto it = std::lower_bound(targets.begin(), targets.end(), p);
      if (it == targets.end() || *it != p) continue;
      seen[static_cast<std::size_t>(it - targets.begin())] = 1;
      mine.push_back(p);
    }
    c.sees.push_back(std::move(mine));
  }
  c.missing_targets = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 0));
  if (c.missing_targets > 0) {
    const auto first = static_cast<std::size_t>(std::find(seen.begin(), seen.end(), 0) - seen.begin());
    fail(fmt::format("{} targets are seen from no stop (the first: POI {})", c.missing_targets, targets[first]));
  }
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) c.recomputed_cost += (stops[i + 1] - stops[i]).norm();
  if (std::abs(c.recomputed_cost - stated_cost) > 1e-9 * std::max(1.0, c.recomputed_cost)) {
    fail(fmt::format("the stated cost {} is not the segments' length {}", stated_cost, c.recomputed_cost));
  }
  return c;
}

}  // namespace ispars::planning
