#pragma once
// The inside of the viewer's server, shared by its HTTP side (web_server.cpp) and its WebSocket
// side (websocket_session.cpp): the server's state, and the helpers both use.

#include <utility>  // before Boost 1.74's asio, whose awaitable.hpp uses std::exchange unincluded

#include <fmt/format.h>
#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <deque>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

#include "ispars/web/access_policy.hpp"
#include "ispars/web/feed_set.hpp"
#include "web_server.hpp"

namespace ispars::web {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

/// A scene name as the daemon accepts it: 1-64 of A-Za-z0-9_-. and not starting with a dot.
bool valid_scene_name(const std::string& name);
/// The page's error message.
std::string error_message(const std::string& what);

/// A connection whose request has not arrived yet: the first to go when the gateway is full, so
/// that idle connections cannot lock users out. Used on the I/O thread only.
class WaitingConnection {
 public:
  virtual ~WaitingConnection() = default;
  /// Closes the connection if its request has still not arrived; whether it did.
  virtual bool evict() = 0;
  /// Whether its request has still not arrived.
  [[nodiscard]] virtual bool waiting() const = 0;
};

/// The server's state: its options, the scenes it follows, its I/O thread and its workers.
class WebServer::Impl {
 public:
  Impl(client::Client& c, WebServerOptions o) : client(c), options(std::move(o)) {}

  client::Client& client;
  const WebServerOptions options;
  std::atomic<std::size_t> connections{0}, browsers{0}, browsers_total{0}, messages{0}, refused{0};
  std::atomic<std::size_t> refused_access{0}, tours{0}, tours_refused{0}, evicted{0}, unread{0};
  FeedSet feeds{client, options.limits, options.max_scenes, options.feed_linger};
  std::unique_ptr<AccessPolicy> access;  // made once the port is bound
  net::thread_pool workers{8};
  std::thread io_thread;
  // Last, so destroyed first: the sessions its queued handlers hold go before what they use.
  net::io_context io{1};
  tcp::acceptor acceptor{io};
  net::steady_timer sweep_timer{io};
  std::deque<std::weak_ptr<WaitingConnection>> waiting;  // oldest first; I/O thread only

  /// A connection's place in max_connections, given back when the last holder goes.
  struct Slot {
    explicit Slot(Impl& s) : server(s) {}
    ~Slot() { --server.connections; }
    Impl& server;
  };

  /// Drops, on a worker, the feeds no browser watches any more; then again a second later.
  void sweep();
  /// Listens for the next connection.
  void accept();
  /// Closes the oldest connection still waiting for its request; whether there was one.
  bool evict_a_waiting_connection();
  /// One of the page's files (a fixed list) from the web root, or 404.
  void serve_file(const std::string& name, std::string& type, std::string& body, http::status& status) const;
};

/// Takes over an upgraded connection as a WebSocket that streams `request`'s scene
/// (/ws?scene=NAME) to its browser.
void start_websocket(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot,
                     http::request<http::string_body> request);
/// Whether the upgrade offers the Foxglove WebSocket subprotocol (foxglove.websocket.v1).
bool offers_foxglove(const http::request<http::string_body>& request);
/// Takes over an upgraded connection as a Foxglove WebSocket serving `scene` (foxglove_session.cpp).
void start_foxglove_websocket(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot,
                              http::request<http::string_body> request, std::string scene);

}  // namespace ispars::web
