#include "web_server.hpp"

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

namespace ispars::web {
namespace {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

// A scene name as the daemon accepts it: 1-64 of A-Za-z0-9_-. and not starting with a dot.
bool valid_scene_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; });
}

std::string error_message(const std::string& what) { return nlohmann::json{{"type", "error"}, {"message", what}}.dump(); }

// The value of `key` in a target's query string ("/ws?scene=s0"), undecoded: names need no escapes.
std::string query_value(std::string_view target, std::string_view key) {
  const auto q = target.find('?');
  if (q == std::string_view::npos) return {};
  std::string_view rest = target.substr(q + 1);
  while (!rest.empty()) {
    const auto amp = rest.find('&');
    const std::string_view pair = rest.substr(0, amp);
    if (pair.size() > key.size() && pair.substr(0, key.size()) == key && pair[key.size()] == '=') {
      return std::string(pair.substr(key.size() + 1));
    }
    if (amp == std::string_view::npos) break;
    rest = rest.substr(amp + 1);
  }
  return {};
}

}  // namespace

class WebServer::Impl {
 public:
  Impl(client::Client& c, WebServerOptions o) : client(c), options(std::move(o)) {}

  client::Client& client;
  const WebServerOptions options;
  std::atomic<std::size_t> connections{0}, browsers{0}, browsers_total{0}, messages{0}, refused{0};
  std::mutex feeds_mutex;
  std::map<std::string, std::shared_ptr<SceneFeed>> feeds;
  net::thread_pool workers{8};
  std::thread io_thread;
  // Last, so destroyed first: the sessions its queued handlers hold go before what they use.
  net::io_context io{1};
  tcp::acceptor acceptor{io};

  // A connection's place in max_connections, given back when the last holder goes.
  struct Slot {
    explicit Slot(Impl& s) : server(s) {}
    ~Slot() { --server.connections; }
    Impl& server;
  };

  // The feed of `scene`, made on first use (blocks: run on a worker).
  std::shared_ptr<SceneFeed> feed_for(const std::string& scene) {
    {
      std::lock_guard lock(feeds_mutex);
      if (auto it = feeds.find(scene); it != feeds.end()) return it->second;
      if (feeds.size() >= options.max_scenes) {
        throw std::runtime_error(fmt::format("the viewer follows {} scenes already (its limit)", feeds.size()));
      }
    }
    auto feed = std::make_shared<SceneFeed>(client, scene, options.limits);  // outside the lock: it waits
    std::lock_guard lock(feeds_mutex);
    return feeds.emplace(scene, std::move(feed)).first->second;  // a feed made meanwhile wins
  }

  void accept();
  void serve_file(const std::string& name, std::string& type, std::string& body, http::status& status) const {
    static const std::map<std::string, std::string> kFiles = {{"index.html", "text/html; charset=utf-8"},
                                                              {"app.js", "text/javascript"},
                                                              {"three.module.js", "text/javascript"},
                                                              {"three.core.js", "text/javascript"},
                                                              {"OrbitControls.js", "text/javascript"}};
    const auto it = kFiles.find(name);
    std::ifstream in(options.web_root / name, std::ios::binary);
    if (it == kFiles.end() || !in) {
      status = http::status::not_found;
      type = "text/plain";
      body = it == kFiles.end() ? "not found\n" : name + " is missing from the web root " + options.web_root.string() + "\n";
      return;
    }
    std::ostringstream text;
    text << in.rdbuf();
    status = http::status::ok;
    type = it->second;
    body = text.str();
  }
};

namespace {

using Server = WebServer::Impl;

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Server* server, std::shared_ptr<Server::Slot> slot)
      : ws_(std::move(socket)), timer_(ws_.get_executor()), server_(server), slot_(std::move(slot)) {}

  void run(http::request<http::string_body> request) {
    const std::string target(request.target());
    scene_ = query_value(target, "scene");
    ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(64 * 1024);
    ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
      if (!ec) self->opened();
    });
  }

 private:
  void opened() {
    ++server_->browsers;
    ++server_->browsers_total;
    counted_ = true;
    read();
    if (!valid_scene_name(scene_)) {
      send(error_message("scene: '" + scene_ + "' is not a scene name (1-64 of A-Za-z0-9_-.)"));
      return;
    }
    net::post(server_->workers, [self = shared_from_this()] {
      try {
        auto feed = self->server_->feed_for(self->scene_);
        net::post(self->ws_.get_executor(), [self, feed] {
          self->feed_ = feed;
          self->tick();
        });
      } catch (const std::exception& e) {
        const std::string m = error_message(e.what());
        net::post(self->ws_.get_executor(), [self, m] { self->send(m); });
      }
    });
  }

  void read() {
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      const std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      self->on_message(text);
      self->read();
    });
  }

  void on_message(const std::string& text) {
    nlohmann::json m = nlohmann::json::parse(text, nullptr, false);
    if (m.is_discarded() || !m.is_object() || !m.contains("type") || !m["type"].is_string()) {
      return send(error_message("request: not a JSON object with a type"));
    }
    if (m["type"] != "tour") return send(error_message("request: type: '" + m["type"].dump() + "' is not tour"));
    if (m.contains("budget") && !m["budget"].is_number()) return send(error_message("tour: budget: not a number"));
    const double budget = m.value("budget", 2.0);
    if (!(budget >= 0.1 && budget <= server_->options.tour_budget_max)) {
      return send(error_message(fmt::format("tour: budget: must be 0.1..{} seconds", server_->options.tour_budget_max)));
    }
    if (tour_running_) return send(error_message("tour: this page's last tour is still searching"));
    if (!feed_) return send(error_message("tour: the scene is not followed yet"));
    tour_running_ = true;
    net::post(server_->workers, [self = shared_from_this(), budget] {
      std::string reply;
      try {
        const msg::Reply r = self->server_->client.tour(self->scene_, budget, 1, {});
        nlohmann::json positions = nlohmann::json::array();
        for (const auto& p : r.body().tour().waypoints()) positions.push_back({p.x(), p.y(), p.z()});
        reply = nlohmann::json{{"type", "tour"},
                               {"cost", r.body().tour().cost()},
                               {"covered", r.body().tour().covered()},
                               {"targets", r.body().tour().target_count()},
                               {"valid", r.body().tour().valid()},
                               {"positions", positions}}
                    .dump();
      } catch (const std::exception& e) {
        reply = error_message(std::string("tour: ") + e.what());
      }
      net::post(self->ws_.get_executor(), [self, reply] {
        self->tour_running_ = false;
        self->send(reply);
      });
    });
  }

  void tick() {
    if (closed_) return;
    // A slow browser: nothing more is queued until its socket drains; it then gets everything new
    // at once (the cursor only moves when messages are queued).
    if (queue_.size() < server_->options.max_queued_messages) {
      try {
        for (std::string& m : feed_->updates_for(cursor_)) send(std::move(m));
      } catch (const std::exception& e) {
        send(error_message(e.what()));
      }
    }
    timer_.expires_after(std::chrono::milliseconds(200));
    timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (!ec) self->tick();
    });
  }

  void send(std::string message) {
    if (closed_) return;
    queue_.push_back(std::make_shared<std::string>(std::move(message)));
    if (queue_.size() == 1) write();
  }

  void write() {
    ws_.text(true);
    ws_.async_write(net::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();  // the browser went away mid-stream: this session ends, the others go on
      ++self->server_->messages;
      self->queue_.pop_front();
      if (!self->queue_.empty()) self->write();
    });
  }

  void close() {
    if (closed_) return;
    closed_ = true;
    timer_.cancel();
    queue_.clear();
    if (counted_) --server_->browsers;
  }

  websocket::stream<beast::tcp_stream> ws_;
  beast::flat_buffer buffer_;
  net::steady_timer timer_;
  Server* server_;
  std::shared_ptr<Server::Slot> slot_;
  std::string scene_;
  std::shared_ptr<SceneFeed> feed_;
  ViewerCursor cursor_;
  std::deque<std::shared_ptr<std::string>> queue_;
  bool closed_ = false;
  bool counted_ = false;
  bool tour_running_ = false;
};

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server* server)
      : stream_(std::move(socket)), server_(server), slot_(std::make_shared<Server::Slot>(*server_)) {}

  void run() {
    stream_.expires_after(std::chrono::seconds(30));
    parser_.body_limit(16 * 1024);
    http::async_read(stream_, buffer_, parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (!ec) self->handle();
    });
  }

 private:
  void handle() {
    http::request<http::string_body> request = parser_.release();
    const std::string target(request.target());
    const std::string path = target.substr(0, target.find('?'));
    version_ = request.version();
    if (websocket::is_upgrade(request)) {
      if (path != "/ws") return respond(http::status::not_found, "text/plain", "WebSockets are at /ws?scene=NAME\n");
      stream_.expires_never();
      std::make_shared<WsSession>(stream_.release_socket(), server_, slot_)->run(std::move(request));
      return;
    }
    if (request.method() != http::verb::get) return respond(http::status::method_not_allowed, "text/plain", "GET only\n");
    if (path == "/api/scenes") {
      return net::post(server_->workers, [self = shared_from_this()] {
        http::status status = http::status::ok;
        std::string body;
        try {
          nlohmann::json list = nlohmann::json::array();
          for (const auto& e : self->server_->client.list_scenes()) {
            list.push_back({{"name", e.name().to_string()}, {"server_id", e.server_id().to_string()},
                            {"loaded", e.loaded()}, {"has_roadmap", e.has_roadmap()}});
          }
          body = nlohmann::json{{"scenes", list}}.dump();
        } catch (const std::exception& e) {
          status = http::status::service_unavailable;
          body = nlohmann::json{{"error", e.what()}}.dump();
        }
        net::post(self->stream_.get_executor(), [self, status, body] { self->respond(status, "application/json", body); });
      });
    }
    if (path.rfind("/api/mesh/", 0) == 0) {
      const std::string scene = path.substr(10);
      if (!valid_scene_name(scene)) return respond(http::status::bad_request, "text/plain", "not a scene name\n");
      return net::post(server_->workers, [self = shared_from_this(), scene] {
        http::status status = http::status::ok;
        std::string type = "application/octet-stream", body;
        try {
          std::string why;
          const auto mesh = self->server_->feed_for(scene)->mesh(self->server_->options.scene_dir, why);
          if (mesh) {
            body = *mesh;
          } else {
            status = http::status::not_found;
            type = "text/plain";
            body = why + "\n";
          }
        } catch (const std::exception& e) {
          status = http::status::not_found;
          type = "text/plain";
          body = std::string(e.what()) + "\n";
        }
        net::post(self->stream_.get_executor(), [self, status, type, body] { self->respond(status, type, body); });
      });
    }
    std::string type, body;
    http::status status{};
    server_->serve_file(path == "/" ? "index.html" : path.substr(1), type, body, status);
    respond(status, type, std::move(body));
  }

  void respond(http::status status, const std::string& type, std::string body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, version_);
    response->set(http::field::server, "ispars-web");
    response->set(http::field::content_type, type);
    response->set(http::field::cache_control, "no-store");
    response->keep_alive(false);
    response->body() = std::move(body);
    response->prepare_payload();
    http::async_write(stream_, *response, [self = shared_from_this(), response](beast::error_code, std::size_t) {
      beast::error_code ignored;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    });
  }

  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  http::request_parser<http::string_body> parser_;
  Server* server_;
  std::shared_ptr<Server::Slot> slot_;
  unsigned version_ = 11;
};

}  // namespace

void WebServer::Impl::accept() {
  acceptor.async_accept(net::make_strand(io), [self = this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec == net::error::operation_aborted) return;
    } else if (self->connections >= self->options.max_connections) {
      ++self->refused;  // closed at once: a browser retries
    } else {
      ++self->connections;
      std::make_shared<HttpSession>(std::move(socket), self)->run();
    }
    self->accept();
  });
}

WebServer::WebServer(client::Client& client, WebServerOptions options)
    : impl_(std::make_shared<Impl>(client, std::move(options))) {
  Impl& s = *impl_;
  beast::error_code ec;
  const auto address = net::ip::make_address_v4(s.options.address, ec);
  if (ec) throw std::runtime_error(fmt::format("--listen: '{}' is not an IPv4 address", s.options.address));
  const tcp::endpoint endpoint(address, s.options.port);
  s.acceptor.open(endpoint.protocol(), ec);
  if (!ec) s.acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) s.acceptor.bind(endpoint, ec);
  if (!ec) s.acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error(fmt::format("cannot listen on {}:{}: {}", s.options.address, s.options.port, ec.message()));
  s.accept();
  s.io_thread = std::thread([&s] { s.io.run(); });
}

WebServer::~WebServer() {
  impl_->io.stop();
  if (impl_->io_thread.joinable()) impl_->io_thread.join();
  impl_->workers.join();  // a tour still searching ends within its budget
  std::lock_guard lock(impl_->feeds_mutex);
  impl_->feeds.clear();
}

std::uint16_t WebServer::port() const { return impl_->acceptor.local_endpoint().port(); }

WebServerStats WebServer::stats() const {
  return {impl_->browsers, impl_->browsers_total, impl_->messages, impl_->refused};
}

}  // namespace ispars::web
