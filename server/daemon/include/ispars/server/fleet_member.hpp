#pragma once
// isparsd in a fleet of daemons: joining (listening for the others before claiming anything,
// refusing an id another daemon announces), announcing what it holds, then a thread that applies
// the ownership rule (docs/fleet.md) as the fleet changes: a scene held here that another daemon
// outweighs is handed over to it with the work accepted here, and a scene whose holder left or
// handed it here is taken over (fleet_takeover.cpp).

#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "ispars.h"
#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_metrics.hpp"
#include "ispars/server/fleet_listing.hpp"
#include "ispars/server/scene_claims.hpp"
#include "ispars/server/takeover_gate.hpp"
#include "ispars/server/takeover_runner.hpp"
#include "ispars/server/task_board.hpp"
#include "ispars/service/roadmap_service.hpp"

namespace ispars::server {

class DdsLink;
class StopSignal;

/// Thrown at start when another running daemon announces this daemon's server id.
struct ServerIdTaken : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// isparsd's exit status when another daemon serves its server id (at start, or seen later):
/// systemd must not restart it (RestartPreventExitStatus).
inline constexpr int kExitServerIdTaken = 3;

/// This daemon as one of the fleet: its claims, its announcement, its takeovers and hand-overs.
class FleetMember {
 public:
  /// `leaving` is raised when the daemon stops; `joined_ms` is announced (of two daemons with one
  /// id, the later one stops).
  FleetMember(const DaemonConfig& config, DdsLink& dds, StopSignal& stop, const std::atomic<bool>& leaving,
              std::uint64_t joined_ms);
  ~FleetMember();
  FleetMember(const FleetMember&) = delete;
  FleetMember& operator=(const FleetMember&) = delete;

  /// Announces (holding nothing) and listens for the other daemons; throws ServerIdTaken when
  /// another announces this daemon's id.
  void join();
  /// The service whose scenes this daemon holds, once it exists (before start()); null once it is gone.
  void attach(service::RoadmapService* service) { service_ = service; }
  /// The fleet thread; stop() joins it and the takeovers running (after the StopSignal is raised).
  void start();
  void stop();

  /// From the DDS layer (inside its callbacks): an announcement (or a leave, null), a status, a task.
  void observe(const msg::DaemonInfo* announcement);
  void observe(const msg::SceneStatus& status);
  void observe(const msg::SceneTask& task);
  /// The service's events: a scene claimed (being loaded), released, or the held set changed.
  void claim(const std::string& scene);
  void release(const std::string& scene);
  void announce();

  /// Requests for a scene wait while a takeover resumes it.
  [[nodiscard]] const TakeoverGate& gate() const { return takeover_gate_; }
  /// `scene`'s note for the scenes list (a hand-over, a takeover's outcome), or empty.
  [[nodiscard]] std::string note(const std::string& scene) const { return listing_.note(scene); }
  /// The fleet's part of a scrape.
  void fill_gauges(DaemonGauges& gauges) const;
  /// True once an older daemon with this daemon's id was seen: it has asked itself to stop.
  [[nodiscard]] bool displaced() const { return displaced_; }

 private:
  void watch();  // the fleet thread
  void check_namesakes(std::chrono::steady_clock::time_point& last_reannounce);
  msg::DaemonInfo self_info() const;
  bool refresh_listing();                       // listing_.refresh() with the scenes held; true when it changed
  void give_up(const ContestedScene& contest);  // hands a held scene to the daemon that outweighs this one
  void announce_if_fresher();                   // held roadmaps changed: at once for a new generation or target
  // Takeovers (fleet_takeover.cpp). Those beyond the runner's capacity wait in waiting_takeovers_.
  void start_takeovers(std::vector<OrphanScene> orphans);
  void take_over(const OrphanScene& orphan);  // on a runner's thread
  /// A takeover that failed with `what`: an empty scene is released, the reason noted for the
  /// scenes list, and the takeover is tried again (SceneClaims, with backoff).
  void failed_takeover(const OrphanScene& orphan, const std::string& what);
  /// Carries into each scene held here the task changes of a daemon that handed it here with the
  /// same lineage (the losing side of a partition): merge_tasks, once per change of either list.
  /// Then those of a former owner whose copy a takeover continued (carried_tasks_).
  void merge_handed_tasks();
  /// Applies the first change of merge_tasks(`scene`'s tasks, `theirs`) (an addition is a job:
  /// one a pass); true when there was none left to apply (or it cannot be, logged).
  bool apply_task_merge(const std::string& scene, const std::string& from,
                        std::span<const service::InspectionTask> theirs);

  const DaemonConfig& config_;
  DdsLink& dds_;
  StopSignal& stop_;
  const std::atomic<bool>& leaving_;
  const std::uint64_t joined_ms_;
  service::RoadmapService* service_ = nullptr;
  std::unique_ptr<SceneClaims> claims_;              // DDS callbacks read it
  TaskBoard task_board_;                             // other daemons' tasks, for a takeover's rebuild
  std::map<std::string, std::string> tasks_merged_;  // scene -> the lists last merged (fleet thread)
  /// A takeover that continued this daemon's own copy: the former owner's tasks, merged in once
  /// the scene is idle (merge_tasks; the counts of task events of two histories do not compare).
  struct CarriedTasks {
    std::string from;
    std::vector<service::InspectionTask> tasks;
  };
  std::mutex carried_mutex_;
  std::map<std::string, CarriedTasks> carried_tasks_;  // scene -> (written by takeovers, merged by the fleet thread)
  std::vector<OrphanScene> waiting_takeovers_;         // for a free runner (fleet thread)
  TakeoverGate takeover_gate_;
  std::mutex announce_mutex_;                      // announcements written in the order they were made
  FleetListing listing_;                           // scene files, stored roadmaps, handovers and notes, as announced
  std::vector<service::ServedRoadmap> last_held_;  // held roadmaps as last announced (announce_if_fresher)
  std::chrono::steady_clock::time_point last_held_announce_{};
  TakeoverRunner takeovers_;
  std::thread thread_;
  std::atomic<bool> displaced_{false};
};

}  // namespace ispars::server
