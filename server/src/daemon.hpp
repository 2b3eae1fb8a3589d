#pragma once
// isparsd: the roadmap service (RoadmapService) behind DDS. Requests arrive on the query and
// change topics; each is checked once for its header (ids, protocol version), answered from the
// reply cache when it is a retry, else decoded, handed to the service, and its result encoded
// into the reply. The service's events become status, update and announcement messages.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "daemon_config.hpp"
#include "daemon_metrics.hpp"
#include "fleet_listing.hpp"
#include "ispars.h"
#include "ispars/service/roadmap_service.hpp"
#include "ispars/service/worker_pool.hpp"
#include "ispars/wire/rejoin_schedule.hpp"
#include "reply_cache.hpp"
#include "request_ledger.hpp"
#include "scene_claims.hpp"
#include "systemd_notify.hpp"
#include "takeover_gate.hpp"
#include "takeover_runner.hpp"
#include "task_board.hpp"

namespace ispars::server {

class DdsEndpoints;
class MetricsEndpoint;

/// Thrown at start when another running daemon announces this daemon's server id.
struct ServerIdTaken : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// isparsd's exit status when another daemon serves its server id (at start, or seen later):
/// systemd must not restart it (RestartPreventExitStatus).
inline constexpr int kExitServerIdTaken = 3;

/// This machine's host name ("host" when it cannot be read).
[[nodiscard]] std::string host_name();

/// One isparsd: its data directory (held by a lock file), its DDS endpoints and its service.
class Daemon {
 public:
  /// Joins the domain, reloads every stored roadmap and starts serving. Throws on a bad data
  /// directory, a data directory held by another daemon, or DDS setup failure.
  explicit Daemon(DaemonConfig config);
  /// Same as shutdown().
  ~Daemon();
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// Stops: requests stop being served, running tours reply with their best, running builds
  /// commit their current chunk and stop, final statuses are published, and the participant leaves.
  void shutdown();

  [[nodiscard]] const std::string& server_id() const { return config_.server_id; }
  /// True once an older daemon with this daemon's server id was seen after this one started:
  /// this daemon has then asked itself to stop (SIGTERM to its own process) and exits non-zero.
  [[nodiscard]] bool displaced() const { return displaced_; }

  /// SIGHUP: applies what can change while serving (the log: its file, reopened, and its level)
  /// from `fresh`, and logs the keys that changed but need a restart.
  void reload(const DaemonConfig& fresh);

  /// Called by the DDS layer for every request addressed to this daemon (any thread). Quick
  /// operations (list, stats, cancel, unload, build, extend, tour) are answered on the quick lane,
  /// the others (load, path, snapshot, verify, drop) on the slow lane, so STATS and CANCEL answer
  /// however many slow requests wait. Each lane queues at most config.request_queue requests;
  /// past that a request is refused at once as busy.
  void receive(msg::QueryRequest request);
  void receive(msg::ChangeRequest request);
  /// Called by the DDS layer (inside its callbacks: quick, no DDS calls) when an announcement
  /// changed, and for every status another daemon published.
  /// An announcement arrived (`announcement`, alive) or a daemon left: the fleet thread looks.
  void fleet_changed(const msg::DaemonInfo* announcement = nullptr);
  void status_seen(const msg::SceneStatus& status);
  void task_seen(const msg::SceneTask& task);

 private:
  template <class Request>
  void dispatch(Request request);
  template <class Request>
  void handle(const Request& request);
  template <class Request>
  void refuse_busy(const Request& request, const WorkerPool& lane, const char* lane_name);
  /// Fills `reply` from the service. Returns false when the reply is sent later (a tour).
  bool answer(const msg::QueryRequest& request, msg::Reply& reply);
  bool answer(const msg::ChangeRequest& request, msg::Reply& reply);
  void start_tour(const msg::QueryRequest& request, const msg::Reply& header);
  void finish(const msg::Reply& reply);  // caches the reply, then sends it

  msg::SceneStatus status_message(const RoadmapSession& session) const;
  void publish_status(const RoadmapSession& session);
  void publish_unloaded(const std::string& scene, bool given_up);
  void announce();
  msg::DaemonInfo self_info() const;
  bool refresh_listing();  // listing_.refresh() with the scenes held; true when it changed
  ServiceEvents service_events();
  // The fleet (daemon_fleet.cpp): waiting for the other daemons at start, then a thread that
  // gives up contested scenes and takes over those whose holder left.
  void join_fleet();  // after dds_ exists: listens, refuses a duplicate id
  void watch_fleet();
  void give_up(const ContestedScene& contest);  // hands a held scene to the daemon that outweighs this one
  /// Starts the takeovers of `orphans` beside the fleet thread (TakeoverRunner); those beyond
  /// its capacity wait in waiting_takeovers_ for a later pass.
  void start_takeovers(std::vector<OrphanScene> orphans);
  void take_over(const OrphanScene& orphan);  // on a runner's thread
  /// A takeover that failed with `what`: an empty scene is released, the reason noted for the
  /// scenes list, and the takeover is tried again (SceneClaims, with backoff).
  void failed_takeover(const OrphanScene& orphan, const std::string& what);
  void announce_if_fresher();  // held roadmaps changed: at once for a new generation or target
  /// Carries into each scene held here the task changes of a daemon that handed it here with the
  /// same lineage (the losing side of a partition): merge_tasks, once per change of either list.
  /// Then those of a former owner whose copy a takeover continued (carried_tasks_).
  void merge_handed_tasks();
  /// Applies the first change of merge_tasks(`scene`'s tasks, `theirs`) (an addition is a job:
  /// one a pass); true when there was none left to apply (or it cannot be, logged).
  bool apply_task_merge(const std::string& scene, const std::string& from, std::span<const InspectionTask> theirs);
  // Rejoining (daemon_rejoin.cpp): a peer this one dropped came back under the same GUID,
  // so the sessions between them may never recover (PeerWatch); this daemon then replaces its
  // participant: the new one announces and publishes its statuses again while the old one still
  // announces this daemon, and the old one leaves once the daemons it heard hear the new one.
  void rejoin_if_a_peer_returned();
  void rejoin(const std::string& why);
  // Keeps the old participant beside the new one until the new one has heard every daemon in
  // `heard`; false if it had not when the overlap ran out.
  bool overlap_until_heard(const std::vector<std::string>& heard);
  void mark_version(const std::string& scene, const RoadmapSession& session);  // an empty batch at its version
  // The DDS side, replaced whole by rejoin(). Every use goes through with_dds(), which holds
  // dds_mutex_ shared; rejoin() holds it alone only to swap the pointer, never while a
  // participant is made or deleted (whose callbacks may be waiting for it): the old one is
  // deleted after the overlap, outside the lock.
  template <class F>
  void with_dds(F&& f) const {
    std::shared_lock lock(dds_mutex_);
    if (dds_) f(*dds_);
  }
  [[nodiscard]] std::vector<msg::DaemonInfo> other_daemons() const;
  // For operators (daemon_operator.cpp): readiness, watchdog, metrics and health.
  void open_metrics_endpoint();  // first of all: a port in use stops the start
  void start_serving();          // READY
  void watch_health();           // its own thread: probes the quick lane, pings WATCHDOG
  [[nodiscard]] bool healthy() const;
  [[nodiscard]] std::string metrics_text() const;
  void finish(const msg::Reply& reply, std::chrono::steady_clock::time_point taken);  // counts, then finish()

  DaemonConfig config_;
  int lock_fd_ = -1;
  ReplyCache cache_;
  std::unique_ptr<RequestLedger> ledger_;  // change requests on disk: a retry after a restart is not run again
  mutable std::mutex status_mutex_;        // stamps statuses in order
  mutable std::uint64_t status_seq_ = 0;
  std::mutex publish_mutex_;                         // writes statuses in stamp order
  std::unique_ptr<SceneClaims> claims_;              // made before dds_: DDS callbacks read it
  TaskBoard task_board_;                             // other daemons' tasks, for a takeover's rebuild
  std::map<std::string, std::string> tasks_merged_;  // scene -> the lists last merged (fleet thread)
  /// A takeover that continued this daemon's own copy: the former owner's tasks, merged in once
  /// the scene is idle (merge_tasks; the counts of task events of two histories do not compare).
  struct CarriedTasks {
    std::string from;
    std::vector<InspectionTask> tasks;
  };
  std::mutex carried_mutex_;
  std::map<std::string, CarriedTasks> carried_tasks_;  // scene -> (written by takeovers, merged by the fleet thread)
  std::vector<OrphanScene> waiting_takeovers_;         // for a free runner (fleet thread)
  TakeoverGate takeover_gate_;                         // requests for a scene wait while take_over() resumes it
  std::mutex announce_mutex_;                          // announcements written in the order they were made
  FleetListing listing_;                  // scene files, stored roadmaps, handovers and notes, as announced
  std::vector<ServedRoadmap> last_held_;  // held roadmaps as last announced (announce_if_fresher)
  std::chrono::steady_clock::time_point last_held_announce_{};
  mutable std::shared_mutex dds_mutex_;
  std::unique_ptr<DdsEndpoints> dds_;
  wire::RejoinSchedule rejoin_schedule_{std::chrono::seconds(30), std::chrono::seconds(10)};  // the fleet thread's
  std::unique_ptr<RoadmapService> service_;
  std::unique_ptr<WorkerPool> quick_lane_;  // list, stats, cancel, unload, build, extend, tour
  std::unique_ptr<WorkerPool> slow_lane_;   // load, path, snapshot, verify, drop
  TakeoverRunner takeovers_;                // stopped (joined) in shutdown(), before the service goes
  std::mutex fleet_mutex_;
  std::condition_variable fleet_wake_;
  bool fleet_stop_ = false;
  std::thread fleet_thread_;
  std::atomic<bool> leaving_{false};  // shutting down
  std::atomic<bool> displaced_{false};
  std::uint64_t joined_ms_ = 0;  // announced: of two daemons with one id, the later one stops
  SystemdNotifier notifier_;
  DaemonMetrics metrics_;
  std::unique_ptr<MetricsEndpoint> metrics_endpoint_;
  std::atomic<bool> serving_{false};
  std::atomic<bool> probe_pending_{false};                        // a health probe waits on the quick lane
  std::atomic<std::chrono::steady_clock::rep> last_progress_{0};  // when the quick lane last finished a job
  /// How long this process stood still past the built-in lease (SIGSTOP, a stalled machine), seen
  /// by watch_health; the fleet thread takes it and rejoins (plain DDS too). 0: none.
  std::atomic<std::int64_t> stood_still_ms_{0};
  std::thread watchdog_thread_;
  bool shut_down_ = false;
};

}  // namespace ispars::server
