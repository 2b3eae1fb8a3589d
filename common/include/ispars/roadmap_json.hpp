#pragma once
// The roadmap file format shared by `ispars-lab build --out`, `ispars watch --dump` and
// `ispars snapshot --out`: the scene's root and POIs, and each graph's vertices, visible POIs
// and edges, as JSON.

#include <span>
#include <string>

#include "ispars/roadmap.hpp"

namespace ispars {

/// The JSON text (one line) of a roadmap file. `dense` may be nullptr.
[[nodiscard]] std::string roadmap_file_json(const std::string& scene, const Vec3& root, std::span<const Vec3> pois,
                                            const Roadmap& roadmap, const Roadmap* dense);

}  // namespace ispars
