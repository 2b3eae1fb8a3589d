#pragma once
// What isparsd tells the domain of its scenes: each scene's status, stamped in order; its tasks
// beside the status; committed batches as updates; and, for a new participant after a rejoin,
// an empty batch at each roadmap's version.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "ispars/server/daemon_metrics.hpp"
#include "ispars/server/daemon_outbox.hpp"
#include "ispars/service/roadmap_service.hpp"

namespace ispars::server {

/// Stamps and publishes the service's events. Safe from many threads: statuses are written in
/// the order they were stamped, and a later stamp is never an older state.
class StatusPublisher {
 public:
  /// `leaving` is raised when the daemon stops (its updates are then left as they are).
  StatusPublisher(std::string server_id, DaemonOutbox& out, DaemonMetrics& metrics, const std::atomic<bool>& leaving);

  /// `session`'s status, stamped with the next sequence number.
  [[nodiscard]] msg::SceneStatus status_message(const service::RoadmapSession& session) const;
  /// Publishes `session`'s status (and its tasks when they changed).
  void publish_status(const service::RoadmapSession& session);
  /// `scene` left this daemon: its updates are retired and, unless it was given up to another
  /// daemon (whose statuses are the scene's now), an UNLOADED status follows.
  void publish_unloaded(const std::string& scene, bool given_up);
  /// A committed batch of `scene`'s roadmap.
  void publish_commit(const std::string& scene, const RoadmapBatch& batch, std::uint64_t generation,
                      std::uint64_t samples, std::size_t poi_count);
  /// For a new participant: `session`'s status, then an empty batch at its roadmap's version
  /// (the new update writer keeps none of the old one's batches; a replica behind sees the gap).
  void republish(const std::string& scene, const service::RoadmapSession& session);

 private:
  std::uint64_t next_seq() const;

  std::string server_id_;
  DaemonOutbox& out_;
  DaemonMetrics& metrics_;
  const std::atomic<bool>& leaving_;
  mutable std::mutex stamp_mutex_;  // stamps statuses in order
  mutable std::uint64_t seq_ = 0;
  std::mutex publish_mutex_;  // writes statuses in stamp order
};

}  // namespace ispars::server
