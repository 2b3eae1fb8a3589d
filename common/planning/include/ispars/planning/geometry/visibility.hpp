#pragma once
// The visibility map chi(q): which points of interest a sensor at q sees.

#include <cstdint>
#include <memory>
#include <vector>

#include "ispars/planning/geometry/check_counters.hpp"
#include "ispars/planning/geometry/embree_scene.hpp"
#include "ispars/roadmap/poi_id.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::planning {

/// A line of sight stops this far short of its POI, so the surface the POI lies on (and any
/// surface closer to the POI than this, e.g. at a crease) does not block it. Metres.
inline constexpr double kPoiStandoff = 1e-3;

/// chi(q): the POIs within sensor range of q whose line of sight hits no triangle. Candidates
/// come from a k-d tree radius search, never a scan; each costs one occlusion ray.
/// Immutable after construction; every query is const and thread-safe.
class VisibilityOracle {
 public:
  VisibilityOracle(std::shared_ptr<const EmbreeScene> scene, std::vector<Vec3> pois, double sensor_range);
  ~VisibilityOracle();
  VisibilityOracle(const VisibilityOracle&) = delete;
  VisibilityOracle& operator=(const VisibilityOracle&) = delete;

  /// Replaces `out` with the ids of the POIs visible from q, ascending.
  void visible_pois(const Vec3& q, std::vector<PoiId>& out) const;
  /// The same, returned by value.
  [[nodiscard]] std::vector<PoiId> visible_pois(const Vec3& q) const;
  /// True when the segment from q to POI `id` (less the standoff) hits no triangle. Range is
  /// not checked here.
  [[nodiscard]] bool line_of_sight(const Vec3& q, PoiId id) const;
  /// Replaces `out` with the ids of the POIs within sensor range of q, ascending (no rays).
  void pois_in_range(const Vec3& q, std::vector<PoiId>& out) const;

  [[nodiscard]] const std::vector<Vec3>& pois() const { return pois_; }
  [[nodiscard]] double sensor_range() const { return range_; }
  [[nodiscard]] CheckCounts counts() const { return counters_.snapshot(); }

 private:
  struct KdTree;
  std::shared_ptr<const EmbreeScene> scene_;
  std::vector<Vec3> pois_;
  double range_;
  std::unique_ptr<KdTree> tree_;
  CheckCounters counters_;
};

}  // namespace ispars::planning
