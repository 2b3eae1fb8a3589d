#pragma once
// isparsd for its operator: READY, STOPPING and WATCHDOG to systemd, the /metrics and /healthz
// endpoint (healthy: the quick lane finishes work and, without DDS Security, the daemon hears its
// own probe through its sockets), and SIGHUP's reload of the log.

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_metrics.hpp"
#include "ispars/server/systemd_notify.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::server {

class DdsLink;
class MetricsEndpoint;
class StopSignal;

/// The daemon's face to systemd and to a metrics scraper, and its health watchdog thread.
class OperatorEndpoints {
 public:
  /// Fills a part of a scrape from another part of the daemon (any thread).
  using Gauges = std::function<void(DaemonGauges&)>;
  /// `fleet` fills the fleet's part of every scrape (it exists from the start).
  OperatorEndpoints(const DaemonConfig& config, DaemonMetrics& metrics, DdsLink& dds, StopSignal& stop,
                    const std::atomic<bool>& leaving, Gauges fleet);
  ~OperatorEndpoints();
  OperatorEndpoints(const OperatorEndpoints&) = delete;
  OperatorEndpoints& operator=(const OperatorEndpoints&) = delete;

  /// Opens the metrics endpoint, if configured: first of all, so a port in use stops the start.
  /// Until serving, a scrape sees only the counters, and /healthz says 503.
  void open_metrics();
  /// READY, then the health watchdog on its own thread, probing `quick_lane` (which outlives
  /// stop()); scrapes read `service` from now on, while serving.
  void start_serving(service::WorkerPool& quick_lane, Gauges service);
  /// STOPPING with `why`: /healthz says 503 from now on.
  void stopping(const std::string& why);
  /// Joins the watchdog thread (the StopSignal raised first).
  void stop();
  /// Closes the metrics endpoint (before the service and the DDS link go: it reads both).
  void close_metrics();
  /// SIGHUP: reopens the log from `fresh` into `config`, and logs the keys that changed but need
  /// a restart.
  void reload(DaemonConfig& config, const DaemonConfig& fresh);

  [[nodiscard]] bool healthy() const;
  [[nodiscard]] std::string metrics_text() const;

 private:
  void watch_health(service::WorkerPool& quick_lane);  // its own thread: probes the quick lane, pings WATCHDOG
  void probe_dds();

  const DaemonConfig& config_;
  DaemonMetrics& metrics_;
  DdsLink& dds_;
  StopSignal& stop_;
  const std::atomic<bool>& leaving_;
  Gauges fleet_gauges_;
  Gauges service_gauges_;
  SystemdNotifier notifier_;
  std::unique_ptr<MetricsEndpoint> endpoint_;
  std::atomic<bool> serving_{false};
  std::atomic<bool> probe_pending_{false};                        // a health probe waits on the quick lane
  std::atomic<std::chrono::steady_clock::rep> last_progress_{0};  // when the quick lane last finished a job
  std::thread watchdog_;
};

}  // namespace ispars::server
