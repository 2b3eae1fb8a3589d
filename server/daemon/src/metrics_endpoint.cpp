#include "ispars/server/metrics_endpoint.hpp"

#include <fmt/format.h>
#include <httplib.h>
#include <sys/socket.h>

#include <chrono>
#include <stdexcept>

namespace ispars::server {

MetricsEndpoint::MetricsEndpoint(const ListenAddress& address, std::function<std::string()> metrics,
                                 std::function<bool()> healthy)
    : server_(std::make_unique<httplib::Server>()) {
  httplib::Server& s = *server_;
  s.new_task_queue = [] { return new httplib::ThreadPool(2); };
  // httplib's default adds SO_REUSEPORT, which lets a second daemon bind the same port and take
  // half the scrapes: only SO_REUSEADDR here (a restart may rebind at once), so a port in use fails.
  s.set_socket_options([](int sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  s.set_payload_max_length(1024);  // GET only: no body of any size is wanted
  s.set_read_timeout(2, 0);
  s.set_write_timeout(5, 0);
  // One request per connection: two idle keep-alive scrapers would otherwise hold both workers.
  s.set_keep_alive_max_count(1);
  s.Get("/metrics", [metrics = std::move(metrics)](const httplib::Request&, httplib::Response& res) {
    res.set_content(metrics(), "text/plain; version=0.0.4; charset=utf-8");
  });
  s.Get("/healthz", [healthy = std::move(healthy)](const httplib::Request&, httplib::Response& res) {
    const bool ok = healthy();
    res.status = ok ? 200 : 503;
    res.set_content(ok ? "ok\n" : "not serving\n", "text/plain; charset=utf-8");
  });
  // Any other method on the two paths: 405 (before routing, so OPTIONS or a large body get it
  // too); any other path: 404.
  s.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
    if ((req.path == "/metrics" || req.path == "/healthz") && req.method != "GET" && req.method != "HEAD") {
      res.status = 405;
      res.set_header("Allow", "GET, HEAD");
      res.set_content("only GET\n", "text/plain; charset=utf-8");
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  if (address.port == 0) {
    port_ = s.bind_to_any_port(address.host);
  } else {
    port_ = s.bind_to_port(address.host, address.port) ? address.port : -1;
  }
  if (port_ <= 0) {
    throw std::runtime_error(fmt::format("metrics: cannot listen on {}:{} (in use, or not an address of this host)",
                                         address.host, address.port));
  }
  thread_ = std::thread([this] { server_->listen_after_bind(); });
  // Listening before the constructor returns: stop() in the destructor then always ends it.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!server_->is_running()) {
    if (std::chrono::steady_clock::now() > deadline) {
      server_->stop();
      thread_.join();
      throw std::runtime_error(fmt::format("metrics: {}:{} bound but not listening", address.host, port_));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

MetricsEndpoint::~MetricsEndpoint() {
  server_->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace ispars::server
