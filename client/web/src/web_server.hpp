#pragma once
// The live viewer's HTTP and WebSocket server (Boost.Beast, one I/O thread): the page and its
// scripts from a web root, the scene list, each scene's mesh, and one WebSocket per browser that
// streams a scene's roadmap as it grows, its status, and tours on request. Calls that wait on
// the daemons run on worker threads, never on the I/O thread.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "ispars/client/client.hpp"
#include "ispars/web/access_policy.hpp"
#include "ispars/web/scene_feed.hpp"

namespace ispars::web {

/// Where and how the gateway serves. Every bound is checked by the command line.
struct WebServerOptions {
  std::string address = "127.0.0.1";              ///< An IPv4 address to bind (localhost unless told otherwise).
  std::uint16_t port = 8080;                      ///< 0: a free port (see WebServer::port()).
  std::filesystem::path web_root;                 ///< index.html, app.js and the three.js modules.
  std::filesystem::path scene_dir;                ///< Scene YAML files, for the meshes (may be empty).
  std::size_t max_connections = 64;               ///< Browsers and requests at once (1..10,000); when full, the
                                                  ///< oldest connection whose request has not arrived makes room.
  std::size_t max_scenes = 32;                    ///< Scenes followed at once (1..1000).
  std::size_t max_queued_messages = 64;           ///< Per browser: past it, updates wait for the socket.
  std::size_t max_queued_bytes = 32u << 20;       ///< Per browser: past it, updates wait; past twice
                                                  ///< it, a browser that sends and does not read is closed.
  double tour_budget_max = 60.0;                  ///< Seconds a browser may ask a tour to search (0.1..3600).
  std::size_t max_tours = 2;                      ///< Tours searching at once, over every page (1..64).
  std::chrono::milliseconds feed_linger{30'000};  ///< A scene no browser watches is dropped after it (0..3600 s).
  AccessOptions access;                           ///< Origins allowed beyond the gateway's own, and the token.
  DrawLimits limits;
};

/// Counts for the log and the tests.
struct WebServerStats {
  std::size_t browsers = 0;        ///< Open WebSockets.
  std::size_t browsers_total = 0;  ///< WebSockets ever opened.
  std::size_t messages_sent = 0;
  std::size_t refused = 0;         ///< Connections refused over max_connections.
  std::size_t refused_access = 0;  ///< Requests refused by Host, Origin or token.
  std::size_t tours_refused = 0;   ///< Tours refused over max_tours.
  std::size_t scenes = 0;          ///< Scenes followed now.
  std::size_t evicted = 0;         ///< Connections closed, their request not yet sent, to make room.
  std::size_t unread = 0;          ///< WebSockets closed: their browser sent and did not read.
};

class WebServer {
 public:
  /// Binds and starts serving on a thread of its own. Throws std::runtime_error naming the
  /// address and port when it cannot bind.
  WebServer(client::Client& client, WebServerOptions options);
  /// Stops: closes every connection and joins the threads.
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  [[nodiscard]] std::uint16_t port() const;
  [[nodiscard]] WebServerStats stats() const;

  class Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace ispars::web
