#pragma once
// A fingerprint of everything a roadmap built on a scene depends on: the mesh as loaded (after
// scaling), the POIs, and the scene's parameters (bounds, robot radius, sensor range, delta,
// Delta, t, root). A stored roadmap records it, and a daemon compares it with the scene it loads.

#include <string>

#include "ispars/planning/scene/scene.hpp"

namespace ispars::planning {

/// 16 lowercase hex digits (64-bit FNV-1a over the values' bytes, in a fixed order). Equal for
/// equal scenes on any run; any change to a vertex, a triangle, a POI or a parameter changes it
/// (up to 64-bit collisions).
[[nodiscard]] std::string scene_fingerprint(const Scene& scene);

}  // namespace ispars::planning
