#pragma once
// The daemon's HTTP endpoint for operators: GET /metrics (Prometheus text) and GET /healthz
// (200 "ok" while the daemon serves, 503 otherwise). Nothing else is served; every other path or
// method gets 404 or 405. Two worker threads, bodies refused, short timeouts.

#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "ispars/server/daemon_config.hpp"

namespace httplib {
class Server;
}

namespace ispars::server {

class MetricsEndpoint {
 public:
  /// Listens on `address` and serves on its own thread. Throws std::runtime_error naming the
  /// address when it cannot be bound.
  MetricsEndpoint(const ListenAddress& address, std::function<std::string()> metrics, std::function<bool()> healthy);
  /// Stops listening and joins its thread.
  ~MetricsEndpoint();
  MetricsEndpoint(const MetricsEndpoint&) = delete;
  MetricsEndpoint& operator=(const MetricsEndpoint&) = delete;

  /// The port it listens on (the one chosen when the address said 0).
  [[nodiscard]] int port() const { return port_; }

 private:
  std::unique_ptr<httplib::Server> server_;
  int port_ = 0;
  std::thread thread_;
};

}  // namespace ispars::server
