#pragma once
// What the live viewer shows of one scene: a replica of its roadmap kept from the daemon's update
// batches, the scene's mesh from the gateway's scene directory, and the messages that bring a
// browser from what it has drawn to what the replica holds. Knows nothing of HTTP.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ispars/client/client.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/record/scene_update_cursor.hpp"

namespace ispars::web {

/// How much of a roadmap a browser is sent at most; past it, an evenly spread subset is not
/// possible while it grows, so the first vertices and edges are drawn and the page says so.
struct DrawLimits {
  std::size_t vertices = 200'000;    ///< 1..10,000,000
  std::size_t edges = 500'000;       ///< 1..50,000,000
  std::size_t per_message = 20'000;  ///< Vertices or edges in one message (1..1,000,000).
};

/// Where a browser is: the generation it draws, and how much of it it has been sent.
struct ViewerCursor {
  std::uint64_t generation = ~std::uint64_t{0};  ///< Nothing drawn yet.
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::string last_status;  ///< The last status message sent (not resent unchanged).
};

/// One scene followed for any number of browsers. Thread-safe.
class SceneFeed {
 public:
  /// Follows `scene` through `client` (which must outlive the feed). Throws client::ClientError
  /// when no daemon holds the scene.
  SceneFeed(client::Client& client, std::string scene, DrawLimits limits);
  ~SceneFeed();
  SceneFeed(const SceneFeed&) = delete;
  SceneFeed& operator=(const SceneFeed&) = delete;

  /// The next JSON messages for a browser at `cursor` (advanced as they are made): a status when
  /// it changed, then a reset when the roadmap was rebuilt or dropped, then batches of new
  /// vertices and edges. Empty when the browser is up to date.
  std::vector<std::string> updates_for(ViewerCursor& cursor);

  /// The scene's mesh as a binary message (u32 vertex count, u32 triangle count, f32 xyz per
  /// vertex, u32 triangle corners), loaded once from `scene_dir`/SCENE.yaml; nullopt with the
  /// reason in `why` when that file is missing, unreadable or not the daemon's scene (its POIs
  /// differ).
  std::shared_ptr<const std::string> mesh(const std::filesystem::path& scene_dir, std::string& why);

  /// The scene's inspection tasks as a JSON message: each task's name, POI ids and coverage
  /// (asked of the daemon), with its POIs' positions (from the replica) while the tasks' POIs
  /// sent stay within kMaxTaskPoisShown.
  std::string tasks_message();
  static constexpr std::size_t kMaxTaskPoisShown = 50'000;

  /// The next foxglove.SceneUpdate (JSON) for a Foxglove client at `cursor`: what is new in the
  /// replica since, or everything after a rebuild; nullopt when the client is up to date.
  std::optional<std::string> scene_update_for(record::SceneUpdateCursor& cursor);

  [[nodiscard]] const std::string& scene() const { return scene_; }

 private:
  void on_change(const client::ReplicaEvent& event);
  // Logs why the replica's first sync failed, once per reason (the page stays blank meanwhile).
  void log_sync_error();
  // The replica as of its last change, copied when a browser first asks after that change (at
  // most one copy per change and per browser tick, none while no browser watches), with its
  // generation.
  std::shared_ptr<const Roadmap> current(std::uint64_t& generation);
  // Loads the mesh from `scene_dir` (no lock held): the message, or throws naming the problem.
  std::shared_ptr<const std::string> load_mesh(const std::filesystem::path& scene_dir,
                                               const client::RoadmapReplica& replica) const;
  client::Client& client_;
  std::string scene_;
  DrawLimits limits_;
  mutable std::mutex mutex_;
  std::optional<client::SceneStatus> last_status_;    // the last status seen from a live daemon
  std::string logged_sync_error_;                     // the last sync failure logged
  std::atomic<std::uint64_t> changes_{0};             // the replica's changes so far
  std::mutex copy_mutex_;                             // one copy at a time; the others then share it
  std::uint64_t copied_changes_ = ~std::uint64_t{0};  // changes_ when roadmap_ was copied
  std::shared_ptr<const Roadmap> roadmap_;            // under copy_mutex_
  std::uint64_t generation_ = 0;                      // under copy_mutex_
  std::mutex mesh_mutex_;                             // the mesh's state, never held across its load
  std::condition_variable mesh_loaded_;
  bool mesh_loading_ = false;
  std::optional<std::shared_ptr<const std::string>> mesh_;
  std::string mesh_error_;
  std::atomic<client::RoadmapReplica*> replica_ready_{nullptr};  // set once replica_ is constructed
  std::unique_ptr<client::RoadmapReplica> replica_;              // last: its thread calls on_change
};

/// Appends to `out` the messages that bring a browser at `cursor` to `roadmap` (of `generation`),
/// advancing the cursor: a reset when the generation is not the one it draws, then batches of at
/// most `limits.per_message` new vertices and edges, within the draw limits (an edge with an end
/// past the vertex limit is left out, and each batch notes the cut).
void append_roadmap_messages(const Roadmap& roadmap, std::uint64_t generation, const DrawLimits& limits,
                             ViewerCursor& cursor, std::vector<std::string>& out);

/// The JSON of a status message for the page; `daemon_gone`: its daemon has left the domain.
[[nodiscard]] std::string status_message(const client::SceneStatus& status, bool daemon_gone);

}  // namespace ispars::web
