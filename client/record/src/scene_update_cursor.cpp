#include "ispars/record/scene_update_cursor.hpp"

#include <string>

namespace ispars::record {

std::optional<nlohmann::json> SceneUpdateCursor::next(const Roadmap& roadmap, std::uint64_t generation,
                                                      std::size_t snapshots, std::uint64_t time_ns) {
  const bool clear = snapshots != snapshots_ || generation != generation_ || roadmap.vertex_count() < vertices_ ||
                     roadmap.edge_count() < edges_;
  if (!clear && roadmap.vertex_count() == vertices_ && roadmap.edge_count() == edges_) return std::nullopt;
  if (!sized_ && roadmap.vertex_count() > 1) {
    style_.vertex_size = vertex_size_for(roadmap);
    sized_ = true;
  }
  const std::size_t first_vertex = clear ? 0 : vertices_, first_edge = clear ? 0 : edges_;
  nlohmann::json update =
      roadmap_update(roadmap, first_vertex, first_edge, "batch-" + std::to_string(batches_++), clear, style_, time_ns);
  snapshots_ = snapshots;
  generation_ = generation;
  vertices_ = roadmap.vertex_count();
  edges_ = roadmap.edge_count();
  return update;
}

}  // namespace ispars::record
