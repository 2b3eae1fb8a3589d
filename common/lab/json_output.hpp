#pragma once
// JSON helpers shared by the lab's subcommands.

#include <nlohmann/json.hpp>

#include "ispars/planning/geometry/check_counters.hpp"
#include "ispars/roadmap/vec.hpp"

namespace ispars::lab {

inline nlohmann::json to_json(const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); }

inline nlohmann::json to_json(const Aabb& box) { return {{"min", to_json(box.min)}, {"max", to_json(box.max)}}; }

inline nlohmann::json to_json(const planning::CheckCounts& c) {
  return {{"point", c.point}, {"segment", c.segment}, {"rays", c.rays}};
}

}  // namespace ispars::lab
