#pragma once
// Where a follower of a growing roadmap is in its foxglove.SceneUpdate stream (scene_update.hpp):
// what it was sent, so each call sends what is new as one more entity, or, after a rebuild, a
// resync or a shrink, a deletion of everything and the whole roadmap again. `ispars record` and
// the gateway's Foxglove WebSocket both follow a replica with one.

#include <cstdint>
#include <optional>
#include <string>

#include "ispars/record/scene_update.hpp"

namespace ispars::record {

class SceneUpdateCursor {
 public:
  explicit SceneUpdateCursor(SceneStyle style = {}) : style_(std::move(style)) {}

  /// The update that brings a follower from what it was sent to `roadmap` (of `generation`; a
  /// change of `snapshots` means the copy was taken afresh), at `time_ns`; nullopt when nothing
  /// changed. The first call with more than one vertex fixes the sphere size.
  std::optional<nlohmann::json> next(const Roadmap& roadmap, std::uint64_t generation, std::size_t snapshots,
                                     std::uint64_t time_ns);

  [[nodiscard]] const SceneStyle& style() const { return style_; }
  [[nodiscard]] std::size_t vertices() const { return vertices_; }
  [[nodiscard]] std::size_t edges() const { return edges_; }

 private:
  SceneStyle style_;
  bool sized_ = false;
  std::size_t snapshots_ = 0, vertices_ = 0, edges_ = 0, batches_ = 0;
  std::uint64_t generation_ = 0;
};

}  // namespace ispars::record
