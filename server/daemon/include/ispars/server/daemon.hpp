#pragma once
// isparsd: the roadmap service (RoadmapService) behind DDS, as a composition root. It holds the
// data directory's lock and makes the parts in order: the operator endpoints, the DDS link, the
// fleet member (joined before anything is claimed), the service, the status publisher and the
// request router; it stops them in the reverse order, each step named for the stop watchdog.

#include <atomic>
#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <string>

#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_inbox.hpp"
#include "ispars/server/daemon_metrics.hpp"
#include "ispars/server/dds_link.hpp"
#include "ispars/server/fleet_member.hpp"
#include "ispars/server/operator_endpoints.hpp"
#include "ispars/server/request_router.hpp"
#include "ispars/server/status_publisher.hpp"
#include "ispars/server/stop_signal.hpp"
#include "ispars/service/roadmap_service.hpp"

namespace ispars::ros2 {
class Ros2Mirror;
}

namespace ispars::server {

/// One isparsd: its data directory (held by a lock file), its DDS link and its service.
class Daemon final : public DaemonInbox {
 public:
  /// Joins the domain, reloads every stored roadmap and starts serving. Throws on a bad data
  /// directory, a data directory held by another daemon, or DDS setup failure.
  explicit Daemon(DaemonConfig config);
  /// Same as shutdown().
  ~Daemon() override;
  Daemon(const Daemon&) = delete;
  Daemon& operator=(const Daemon&) = delete;

  /// Stops: requests stop being served, running tours reply with their best, running builds
  /// commit their current chunk and stop, final statuses are published, and the participant leaves.
  void shutdown();

  [[nodiscard]] const std::string& server_id() const { return config_.server_id; }
  /// True once an older daemon with this daemon's server id was seen after this one started:
  /// this daemon has then asked itself to stop (SIGTERM to its own process) and exits non-zero.
  [[nodiscard]] bool displaced() const { return fleet_.displaced(); }

  /// SIGHUP: applies what can change while serving (the log: its file, reopened, and its level)
  /// from `fresh`, and logs the keys that changed but need a restart.
  void reload(const DaemonConfig& fresh) { operator_.reload(config_, fresh); }

  /// DaemonInbox: requests go to the router once serving (dropped before: their clients retry),
  /// what is heard of the fleet to the fleet member.
  void receive(msg::QueryRequest request) override;
  void receive(msg::ChangeRequest request) override;
  void fleet_changed(const msg::DaemonInfo* announcement) override { fleet_.observe(announcement); }
  void status_seen(const msg::SceneStatus& status) override { fleet_.observe(status); }
  void task_seen(const msg::SceneTask& task) override { fleet_.observe(task); }

 private:
  void lock_data_dir();
  void serve(std::unique_ptr<RequestLedger> ledger);  // stored roadmaps, preloads, pending jobs, then serving
  [[nodiscard]] service::ServiceSettings service_settings() const;
  service::ServiceEvents service_events();
  void republish();  // every held scene's status and version, from a new participant
  void fill_service_gauges(DaemonGauges& gauges) const;
  void open_ros2();  // the ROS 2 mirror, when config_.ros2

  // Declared in the order they are made; shutdown() stops and releases them in the reverse
  // order explicitly (the metrics endpoint and the DDS link before the service they read).
  DaemonConfig config_;
  int lock_fd_ = -1;
  std::atomic<bool> leaving_{false};  // shutting down
  const std::uint64_t joined_ms_;     // announced: of two daemons with one id, the later one stops
  StopSignal stop_;
  DaemonMetrics metrics_;
  DdsLink dds_;
  StatusPublisher statuses_;
  FleetMember fleet_;
  OperatorEndpoints operator_;
  std::unique_ptr<ros2::Ros2Mirror> ros2_;  // stopped before the service it reads goes
  std::unique_ptr<service::RoadmapService> service_;
  std::unique_ptr<RequestRouter> router_;
  std::shared_mutex receiving_;       // held shared by each receive(); alone when serving_ is cleared
  RequestRouter* serving_ = nullptr;  // router_ while requests are taken
  bool shut_down_ = false;
};

}  // namespace ispars::server
