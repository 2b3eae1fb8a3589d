#pragma once
// A roadmap and a tour as foxglove.SceneUpdate messages (JSON, @foxglove/schemas' SceneUpdate):
// what Foxglove's 3D panel draws from an MCAP file or a WebSocket. A roadmap goes out batch by
// batch, each batch one entity of its own (spheres for its new vertices, one LINE_LIST for its new
// edges) beside the earlier ones; a rebuild or a resync first deletes them all. A tour is one
// entity "tour", a LINE_STRIP through its stops.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::record {

/// Now, in nanoseconds since the epoch: the time of every entity, MCAP message and Foxglove frame.
[[nodiscard]] std::uint64_t now_ns();

/// The JSON Schema of foxglove.SceneUpdate, as @foxglove/schemas 2.1.0 publishes it (MIT).
[[nodiscard]] const std::string& scene_update_schema();

/// How entities are drawn: their frame and sizes.
struct SceneStyle {
  std::string frame = "map";
  double vertex_size = 0.1;     ///< a vertex sphere's diameter, in the scene's units
  double edge_thickness = 1.5;  ///< pixels (scale invariant)
};

/// The vertices from `first_vertex` and the edges from `first_edge` of `roadmap` as entity `id`,
/// at `time_ns` (nanoseconds since the epoch); `clear` deletes every earlier entity first.
[[nodiscard]] nlohmann::json roadmap_update(const Roadmap& roadmap, std::size_t first_vertex, std::size_t first_edge,
                                            const std::string& id, bool clear, const SceneStyle& style,
                                            std::uint64_t time_ns);
/// The tour through `stops` as entity "tour" (replacing the last one).
[[nodiscard]] nlohmann::json tour_update(std::span<const Vec3> stops, const SceneStyle& style, std::uint64_t time_ns);
/// A sphere size for `roadmap`: a 300th of the diagonal of the box around its vertices (0.1 for
/// fewer than two).
[[nodiscard]] double vertex_size_for(const Roadmap& roadmap);

}  // namespace ispars::record
