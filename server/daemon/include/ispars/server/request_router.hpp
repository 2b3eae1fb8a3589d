#pragma once
// isparsd's request path: every request through one template (its client id, the ledger and the
// reply cache for retries, a lane), then on a lane the header checks (protocol, sequence), the
// service's answer and the reply, counted in the metrics, cached, then sent.

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "ispars/server/daemon_metrics.hpp"
#include "ispars/server/daemon_outbox.hpp"
#include "ispars/server/reply_cache.hpp"
#include "ispars/server/request_ledger.hpp"
#include "ispars/server/status_publisher.hpp"
#include "ispars/server/takeover_gate.hpp"
#include "ispars/service/roadmap_service.hpp"
#include "ispars/service/worker_pool.hpp"

namespace ispars::server {

/// Routes requests to the service on two lanes. Quick operations (list, stats, cancel, unload,
/// build, extend, tour, drop) take the quick lane, the others (load, path, snapshot, verify,
/// task add, task list) the slow one, so STATS and CANCEL answer however many slow requests wait.
/// Each lane queues at most `request_queue` requests; past that a request is refused as busy.
class RequestRouter {
 public:
  /// What the router answers with; each part outlives it.
  struct Parts {
    std::string server_id;
    std::size_t request_queue = 256;
    service::RoadmapService& service;
    StatusPublisher& statuses;
    DaemonOutbox& out;
    DaemonMetrics& metrics;
    const TakeoverGate& gate;                             // requests for a scene being taken over wait
    std::function<std::string(const std::string&)> note;  // a scene's note for the scenes list
  };
  /// `ledger`: change requests on disk, so a retry after a restart is not run again.
  RequestRouter(Parts parts, std::unique_ptr<RequestLedger> ledger);
  ~RequestRouter();
  RequestRouter(const RequestRouter&) = delete;
  RequestRouter& operator=(const RequestRouter&) = delete;

  /// Any thread (the DDS layer's): settles a retry at once, else queues the request on its lane.
  void receive(msg::QueryRequest request);
  void receive(msg::ChangeRequest request);
  /// Requests being answered finish; queued ones are dropped (their clients retry elsewhere).
  void stop();
  /// The quick lane, whose progress the health watchdog reads.
  [[nodiscard]] service::WorkerPool& quick_lane() { return quick_lane_; }

 private:
  template <class Request>
  void dispatch(Request request);
  template <class Request>
  void refuse_busy(const Request& request, const service::WorkerPool& lane, const char* lane_name);
  template <class Request>
  void handle(const Request& request);
  /// Fills `reply` from the service (request_answers.cpp). False when the reply is sent later (a tour).
  bool answer(const msg::QueryRequest& request, msg::Reply& reply);
  bool answer(const msg::ChangeRequest& request, msg::Reply& reply);
  void start_tour(const msg::QueryRequest& request, const msg::Reply& header);
  /// Counts `reply` in the metrics, records it in the ledger and the cache, then sends it.
  void finish(const msg::Reply& reply, std::chrono::steady_clock::time_point taken);

  Parts parts_;
  std::unique_ptr<RequestLedger> ledger_;
  ReplyCache cache_;
  service::WorkerPool quick_lane_;
  service::WorkerPool slow_lane_;
};

}  // namespace ispars::server
