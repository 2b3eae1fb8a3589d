#include "ispars/server/operator_endpoints.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ispars/server/daemon_log.hpp"
#include "ispars/server/daemon_settings.hpp"
#include "ispars/server/dds_endpoints.hpp"
#include "ispars/server/dds_link.hpp"
#include "ispars/server/metrics_endpoint.hpp"
#include "ispars/server/stop_signal.hpp"
#include "ispars/wire/participant.hpp"

namespace ispars::server {
namespace {

using Clock = std::chrono::steady_clock;

// The DDS probe (watch_health, self_probe.hpp): the daemon writes a probe sample this often, and
// is healthy only while one came back within the limit (or the watchdog's, if longer).
constexpr std::chrono::seconds kSelfProbePeriod{2};
constexpr std::chrono::seconds kSelfHearingLimit{10};

}  // namespace

OperatorEndpoints::OperatorEndpoints(const DaemonConfig& config, DaemonMetrics& metrics, DdsLink& dds, StopSignal& stop,
                                     const std::atomic<bool>& leaving, Gauges fleet)
    : config_(config), metrics_(metrics), dds_(dds), stop_(stop), leaving_(leaving), fleet_gauges_(std::move(fleet)) {}

OperatorEndpoints::~OperatorEndpoints() {
  stop();
  close_metrics();
}

void OperatorEndpoints::open_metrics() {
  if (!config_.metrics) return;
  const ListenAddress& at = *config_.metrics;
  endpoint_ = std::make_unique<MetricsEndpoint>(
      at, [this] { return metrics_text(); }, [this] { return healthy(); });
  spdlog::info("metrics on http://{}:{}/metrics, health on /healthz", at.host, endpoint_->port());
}

void OperatorEndpoints::start_serving(service::WorkerPool& quick_lane, Gauges service) {
  service_gauges_ = std::move(service);
  last_progress_ = Clock::now().time_since_epoch().count();
  serving_ = true;
  // READY before the first ping: the watchdog thread may run before this thread is scheduled again.
  notifier_.ready(fmt::format("serving on DDS domain {} as {}", config_.participant.domain, config_.server_id));
  watchdog_ = std::thread([this, &quick_lane] { watch_health(quick_lane); });
}

void OperatorEndpoints::stopping(const std::string& why) {
  serving_ = false;
  notifier_.stopping(why);
}

void OperatorEndpoints::stop() {
  if (watchdog_.joinable()) watchdog_.join();
}

void OperatorEndpoints::close_metrics() { endpoint_.reset(); }

void OperatorEndpoints::watch_health(service::WorkerPool& quick_lane) {
  // The quick lane answers STATS and CANCEL: when it stops finishing work, the daemon is wedged,
  // and systemd (WatchdogSec) should restart it. A probe keeps a job there while nothing else
  // runs; the lane counts as alive while its finished-job count moves. Its own thread, so that a
  // slow takeover or a long load on the fleet thread never delays a ping.
  std::uint64_t seen = quick_lane.completed();
  auto last_ping = Clock::now() - std::chrono::hours(1);
  auto last_probe = Clock::now();
  auto last_tick = Clock::now();
  while (stop_.idle_for(std::chrono::milliseconds(100))) {
    // A 100 ms wait that took past the lease: the process was stopped (or its machine stalled),
    // and its peers have dropped it; the fleet thread rejoins.
    // (Plain DDS: under DDS Security the lease is longer and the peers' rejoins handle it.)
    if (const auto gap = Clock::now() - last_tick;
        config_.participant.security.empty() &&
        gap > std::chrono::seconds(wire::lease_seconds(config_.participant.lease_seconds, false))) {
      dds_.note_stood_still(std::chrono::duration_cast<std::chrono::milliseconds>(gap).count());
      stop_.wake();
    }
    last_tick = Clock::now();
    if (Clock::now() - last_probe >= kSelfProbePeriod) {
      last_probe = Clock::now();
      probe_dds();
    }
    if (const std::uint64_t done = quick_lane.completed(); done != seen) {
      seen = done;
      last_progress_ = Clock::now().time_since_epoch().count();
    }
    if (!probe_pending_.exchange(true) && !quick_lane.submit([this] { probe_pending_ = false; })) {
      probe_pending_ = false;  // a full lane: its own jobs show whether it moves
    }
    const auto period = notifier_.watchdog_period();
    if (period && healthy() && Clock::now() - last_ping >= *period) {
      last_ping = Clock::now();
      notifier_.watchdog();
    }
  }
}

void OperatorEndpoints::probe_dds() {
  // A sample this daemon must hear back through its sockets.
  dds_.with([](DdsEndpoints& d) {
    if (d.probe() != nullptr) d.probe()->ping();
  });
}

bool OperatorEndpoints::healthy() const {
  if (!serving_ || leaving_) return false;
  // The watchdog's whole timeout (twice its ping period), or 10 s without one.
  const auto limit = notifier_.watchdog_period()
                         ? 2 * *notifier_.watchdog_period()
                         : std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::seconds(10));
  const Clock::time_point progressed{Clock::duration(last_progress_.load())};
  if (Clock::now() - progressed > limit) return false;
  // And DDS: the daemon heard its own probe through its sockets lately (a daemon whose sockets or
  // receive threads died answers no one, though its lanes run). No probe under DDS Security.
  bool heard = false;
  dds_.with([&](const DdsEndpoints& d) {
    const Clock::duration within = std::max<Clock::duration>(limit, kSelfHearingLimit);
    heard = d.probe() == nullptr || Clock::now() - d.probe()->heard() <= within;
  });
  return heard;
}

std::string OperatorEndpoints::metrics_text() const {
  DaemonGauges g;
  // serving_ first: until it is set, the service and the endpoints are being made on another thread.
  if (serving_) {
    if (service_gauges_) service_gauges_(g);
    dds_.with([&](DdsEndpoints& d) {
      g.update_subscribers = d.update_subscribers();
      g.reply_clients = d.reply_clients();
      g.reply_routes = d.reply_routes();
      g.other_daemons = d.other_daemons().size();
    });
  }
  if (fleet_gauges_) fleet_gauges_(g);
  g.resident_bytes = resident_memory_bytes();
  g.memory_budget_bytes = memory_budget_bytes(config_);
  return metrics_.render(g);
}

void OperatorEndpoints::reload(DaemonConfig& config, const DaemonConfig& fresh) {
  notifier_.reloading();
  const bool reopened = reopen_daemon_log(fresh);
  if (reopened) {
    config.log_file = fresh.log_file;
    config.log_file_mb = fresh.log_file_mb;
    config.log_level = fresh.log_level;
  }
  const std::vector<std::string> later = changed_needing_restart(config, fresh);
  spdlog::info("SIGHUP: {} (level {}){}", reopened ? "log reopened" : "log kept", config.log_level,
               later.empty() ? std::string()
                             : fmt::format("; changed but applied only at a restart: {}", fmt::join(later, ", ")));
  notifier_.ready(fmt::format("serving on DDS domain {} as {}", config.participant.domain, config.server_id));
}

}  // namespace ispars::server
