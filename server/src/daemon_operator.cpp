// isparsd for its operator: READY, STOPPING and WATCHDOG to systemd, the /metrics and /healthz
// endpoint (healthy: the quick lane finishes work and, without DDS Security, the daemon hears its
// own probe through its sockets), and SIGHUP's reload.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "daemon.hpp"
#include "daemon_log.hpp"
#include "daemon_settings.hpp"
#include "dds_endpoints.hpp"
#include "ispars/wire/convert.hpp"
#include "metrics_endpoint.hpp"

namespace ispars::server {
namespace {

using Clock = std::chrono::steady_clock;

// The DDS probe (watch_health, self_probe.hpp): the daemon writes a probe sample this often, and
// is healthy only while one came back within the limit (or the watchdog's, if longer).
constexpr std::chrono::seconds kSelfProbePeriod{2};
constexpr std::chrono::seconds kSelfHearingLimit{10};

}  // namespace

void Daemon::open_metrics_endpoint() {
  if (!config_.metrics) return;
  // Before anything runs: a port in use stops the start. Until serving_, a scrape sees only the
  // counters (the service and endpoints are being made), and /healthz says 503.
  const ListenAddress& at = *config_.metrics;
  metrics_endpoint_ = std::make_unique<MetricsEndpoint>(
      at, [this] { return metrics_text(); }, [this] { return healthy(); });
  spdlog::info("metrics on http://{}:{}/metrics, health on /healthz", at.host, metrics_endpoint_->port());
}

void Daemon::start_serving() {
  last_progress_ = Clock::now().time_since_epoch().count();
  serving_ = true;
  // READY before the first ping: the watchdog thread may run before this thread is scheduled again.
  notifier_.ready(fmt::format("serving on DDS domain {} as {}", config_.domain, config_.server_id));
  watchdog_thread_ = std::thread([this] { watch_health(); });
}

void Daemon::watch_health() {
  // The quick lane answers STATS and CANCEL: when it stops finishing work, the daemon is wedged,
  // and systemd (WatchdogSec) should restart it. A probe keeps a job there while nothing else
  // runs; the lane counts as alive while its finished-job count moves. Its own thread, so that a
  // slow takeover or a long load on the fleet thread never delays a ping.
  std::uint64_t seen = quick_lane_->completed();
  auto last_ping = Clock::now() - std::chrono::hours(1);
  auto last_probe = Clock::now();
  auto last_tick = Clock::now();
  std::unique_lock lock(fleet_mutex_);
  while (!fleet_stop_) {
    fleet_wake_.wait_for(lock, std::chrono::milliseconds(100));
    if (fleet_stop_) break;
    // A 100 ms wait that took past the lease: the process was stopped (or its machine stalled),
    // and its peers have dropped it.
    // (Plain DDS: under DDS Security the lease is longer and the peers' rejoins handle it.)
    if (const auto gap = Clock::now() - last_tick;
        config_.security.empty() && gap > std::chrono::seconds(wire::kLeaseSeconds)) {
      stood_still_ms_ = std::chrono::duration_cast<std::chrono::milliseconds>(gap).count();
      fleet_wake_.notify_all();
    }
    last_tick = Clock::now();
    if (Clock::now() - last_probe >= kSelfProbePeriod) {
      // The DDS probe: a sample this daemon must hear back through its sockets.
      last_probe = Clock::now();
      lock.unlock();
      with_dds([](DdsEndpoints& d) {
        if (d.probe() != nullptr) d.probe()->ping();
      });
      lock.lock();
    }
    const std::uint64_t done = quick_lane_->completed();
    if (done != seen) {
      seen = done;
      last_progress_ = Clock::now().time_since_epoch().count();
    }
    if (!probe_pending_.exchange(true) && !quick_lane_->submit([this] { probe_pending_ = false; })) {
      probe_pending_ = false;  // a full lane: its own jobs show whether it moves
    }
    const auto period = notifier_.watchdog_period();
    if (period && healthy() && Clock::now() - last_ping >= *period) {
      last_ping = Clock::now();
      notifier_.watchdog();
    }
  }
}

bool Daemon::healthy() const {
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
  with_dds([&](const DdsEndpoints& d) {
    const Clock::duration within = std::max<Clock::duration>(limit, kSelfHearingLimit);
    heard = d.probe() == nullptr || Clock::now() - d.probe()->heard() <= within;
  });
  return heard;
}

std::string Daemon::metrics_text() const {
  DaemonGauges g;
  // serving_ first: until it is set, service_ and dds_ are being made on another thread.
  if (serving_ && service_) {
    for (const std::string& scene : service_->loaded_scenes()) {
      try {
        const SessionStatus s = service_->stats(scene);
        g.scenes.push_back(
            {scene, std::string(to_string(s.state)), s.samples_done, s.vertices, s.edges, s.poi_count, s.pois_covered});
      } catch (const std::exception&) {
        // unloaded since it was listed
      }
    }
    g.memory_reserved_bytes = service_->budget().reserved();
    g.memory_leased_bytes = service_->budget().leased();
  }
  if (serving_) {
    with_dds([&](DdsEndpoints& d) {
      g.update_subscribers = d.update_subscribers();
      g.reply_clients = d.reply_clients();
      g.reply_routes = d.reply_routes();
      g.other_daemons = d.other_daemons().size();
    });
  }
  g.fleet_tasks_known = task_board_.size();
  g.handed_over = listing_.handed_over();
  g.declined = listing_.declined_now();
  g.unservable = listing_.unservable();
  g.resident_bytes = resident_memory_bytes();
  g.memory_budget_bytes = memory_budget_bytes(config_);
  return metrics_.render(g);
}

void Daemon::finish(const msg::Reply& reply, Clock::time_point taken) {
  const std::string& error = reply.error();
  const RequestOutcome outcome = reply.ok()                              ? RequestOutcome::ok
                                 : error.rfind("internal error", 0) == 0 ? RequestOutcome::failed
                                                                         : RequestOutcome::refused;
  metrics_.count_request(wire::to_string(reply.body()._d()), outcome,
                         std::chrono::duration<double>(Clock::now() - taken).count());
  finish(reply);
}

void Daemon::reload(const DaemonConfig& fresh) {
  notifier_.reloading();
  const bool reopened = reopen_daemon_log(fresh);
  if (reopened) {
    config_.log_file = fresh.log_file;
    config_.log_file_mb = fresh.log_file_mb;
    config_.log_level = fresh.log_level;
  }
  const std::vector<std::string> later = changed_needing_restart(config_, fresh);
  spdlog::info("SIGHUP: {} (level {}){}", reopened ? "log reopened" : "log kept", config_.log_level,
               later.empty() ? std::string()
                             : fmt::format("; changed but applied only at a restart: {}", fmt::join(later, ", ")));
  notifier_.ready(fmt::format("serving on DDS domain {} as {}", config_.domain, config_.server_id));
}

}  // namespace ispars::server
