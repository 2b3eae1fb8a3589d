#pragma once
// What the daemon writes to the domain, as an interface: the DDS link writes it through the
// participant of the moment; unit tests record it.

#include <functional>
#include <string>
#include <vector>

#include "ispars.h"

namespace ispars::server {

/// Everything the request router and the status publisher send: replies, tour progress, roadmap
/// updates, statuses and tasks. Every call is safe from many threads.
class DaemonOutbox {
 public:
  virtual ~DaemonOutbox() = default;
  virtual void send_reply(const msg::Reply& reply) = 0;
  virtual void publish_tour_progress(const msg::TourProgress& progress) = 0;
  virtual void publish_update(const msg::UpdateBatch& batch) = 0;
  /// `scene`'s roadmap was dropped or left this daemon: replicas drop their copy.
  virtual void retire_updates(const std::string& scene) = 0;
  virtual void publish_status(const msg::SceneStatus& status) = 0;
  /// `scene`'s tasks, when its generation or task events differ from those last published;
  /// `tasks` makes them (called only then).
  virtual void publish_tasks(const std::string& scene, std::uint64_t generation, std::uint64_t events,
                             const std::function<std::vector<msg::SceneTask>()>& tasks) = 0;
};

}  // namespace ispars::server
