// The viewer's HTTP side: the listener, one request per connection (the page, the scene list,
// meshes), and the hand-over of WebSocket upgrades to websocket_session.cpp.

#include "web_server_impl.hpp"

#include <spdlog/spdlog.h>

namespace ispars::web {

bool valid_scene_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

std::string error_message(const std::string& what) {
  return nlohmann::json{{"type", "error"}, {"message", what}}.dump();
}

namespace {

using Server = WebServer::Impl;

// How long a connection may take to send its request.
constexpr std::chrono::seconds kRequestDeadline{10};

class HttpSession : public WaitingConnection, public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Server* server)
      : stream_(std::move(socket)), server_(server), slot_(std::make_shared<Server::Slot>(*server_)) {}

  void run() {
    stream_.expires_after(kRequestDeadline);
    parser_.body_limit(16 * 1024);
    if (server_->waiting.size() > 2 * server_->options.max_connections) {
      std::erase_if(server_->waiting, [](const std::weak_ptr<WaitingConnection>& w) {
        const auto c = w.lock();
        return !c || !c->waiting();
      });
    }
    server_->waiting.push_back(shared_from_this());
    http::async_read(stream_, buffer_, parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      self->waiting_ = false;
      if (!ec) self->handle();
    });
  }

  [[nodiscard]] bool waiting() const override { return waiting_; }

  bool evict() override {
    if (!waiting_) return false;
    waiting_ = false;
    beast::error_code ignored;
    stream_.socket().close(ignored);
    return true;
  }

 private:
  void handle() {
    http::request<http::string_body> request = parser_.release();
    const std::string target(request.target());
    const std::string path = target.substr(0, target.find('?'));
    version_ = request.version();
    const AccessVerdict verdict = server_->access->check(facts(request));
    if (verdict.status != 0) {
      ++server_->refused_access;
      return respond(static_cast<http::status>(verdict.status), "text/plain", verdict.reason + "\n");
    }
    set_cookie_ = verdict.set_cookie;
    if (websocket::is_upgrade(request)) {
      if (path != "/ws") return respond(http::status::not_found, "text/plain", "WebSockets are at /ws?scene=NAME\n");
      stream_.expires_never();
      if (offers_foxglove(request)) {
        std::string scene = query_value(target, "scene");
        start_foxglove_websocket(stream_.release_socket(), server_, slot_, std::move(request), std::move(scene));
        return;
      }
      start_websocket(stream_.release_socket(), server_, slot_, std::move(request));
      return;
    }
    if (request.method() != http::verb::get)
      return respond(http::status::method_not_allowed, "text/plain", "GET only\n");
    if (path == "/api/scenes") return list_scenes();
    if (path.rfind("/api/mesh/", 0) == 0) return send_mesh(path.substr(10));
    std::string type, body;
    http::status status{};
    server_->serve_file(path == "/" ? "index.html" : path.substr(1), type, body, status);
    respond(status, type, std::move(body));
  }

  // The scene list, asked of the daemons on a worker.
  void list_scenes() {
    net::post(server_->workers, [self = shared_from_this()] {
      http::status status = http::status::ok;
      std::string body;
      try {
        nlohmann::json list = nlohmann::json::array();
        for (const auto& e : self->server_->client.list_scenes()) {
          list.push_back(
              {{"name", e.scene}, {"server_id", e.server_id}, {"loaded", e.loaded}, {"has_roadmap", e.has_roadmap}});
        }
        body = nlohmann::json{{"scenes", list}}.dump();
      } catch (const std::exception& e) {
        status = http::status::service_unavailable;
        body = nlohmann::json{{"error", e.what()}}.dump();
      }
      net::post(self->stream_.get_executor(),
                [self, status, body] { self->respond(status, "application/json", body); });
    });
  }

  // A scene's mesh, loaded on a worker.
  void send_mesh(const std::string& scene) {
    if (!valid_scene_name(scene)) return respond(http::status::bad_request, "text/plain", "not a scene name\n");
    net::post(server_->workers, [self = shared_from_this(), scene] {
      http::status status = http::status::ok;
      std::string type = "application/octet-stream", body;
      try {
        std::string why;
        const auto mesh = self->server_->feeds.get(scene)->mesh(self->server_->options.scene_dir, why);
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

  // What the access policy looks at: the request's headers and the connection's two ends.
  RequestFacts facts(const http::request<http::string_body>& request) const {
    const auto sv = [](beast::string_view v) { return std::string_view(v.data(), v.size()); };
    RequestFacts f;
    if (const auto it = request.find(http::field::host); it != request.end()) f.host = sv(it->value());
    if (const auto it = request.find(http::field::origin); it != request.end()) f.origin = sv(it->value());
    f.authorization = sv(request[http::field::authorization]);
    f.cookie = sv(request[http::field::cookie]);
    f.forwarded_proto = sv(request["X-Forwarded-Proto"]);
    f.target = sv(request.target());
    beast::error_code ec;
    f.peer = stream_.socket().remote_endpoint(ec).address().to_string();
    f.local = stream_.socket().local_endpoint(ec).address().to_string();
    return f;
  }

  void respond(http::status status, const std::string& type, std::string body) {
    auto response = std::make_shared<http::response<http::string_body>>(status, version_);
    response->set(http::field::server, "ispars-web");
    if (!set_cookie_.empty()) response->set(http::field::set_cookie, set_cookie_);
    if (status == http::status::unauthorized) response->set(http::field::www_authenticate, "Bearer");
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
  std::string set_cookie_;  // the token's cookie, for a request let in by ?token=
  bool waiting_ = true;     // its request has not arrived
};

}  // namespace

void WebServer::Impl::sweep() {
  sweep_timer.expires_after(std::chrono::seconds(1));
  sweep_timer.async_wait([this](beast::error_code ec) {
    if (ec) return;
    net::post(workers, [this] {
      for (const std::string& scene : feeds.sweep()) {
        spdlog::info("ispars-web: stopped following scene {}: no browser watched it for {} s", scene,
                     std::chrono::duration<double>(options.feed_linger).count());
      }
      net::post(io, [this] { sweep(); });
    });
  });
}

void WebServer::Impl::serve_file(const std::string& name, std::string& type, std::string& body,
                                 http::status& status) const {
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
    body =
        it == kFiles.end() ? "not found\n" : name + " is missing from the web root " + options.web_root.string() + "\n";
    return;
  }
  std::ostringstream text;
  text << in.rdbuf();
  status = http::status::ok;
  type = it->second;
  body = text.str();
}

void WebServer::Impl::accept() {
  acceptor.async_accept(net::make_strand(io), [self = this](beast::error_code ec, tcp::socket socket) {
    if (ec) {
      if (ec == net::error::operation_aborted) return;
    } else if (self->connections >= self->options.max_connections && !self->evict_a_waiting_connection()) {
      ++self->refused;  // closed at once: a browser retries
    } else {
      ++self->connections;
      std::make_shared<HttpSession>(std::move(socket), self)->run();
    }
    self->accept();
  });
}

bool WebServer::Impl::evict_a_waiting_connection() {
  while (!waiting.empty()) {
    const auto oldest = waiting.front().lock();
    waiting.pop_front();
    if (oldest && oldest->evict()) {
      ++evicted;
      return true;
    }
  }
  return false;
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
  if (ec)
    throw std::runtime_error(
        fmt::format("cannot listen on {}:{}: {}", s.options.address, s.options.port, ec.message()));
  s.access = std::make_unique<AccessPolicy>(s.options.access, s.acceptor.local_endpoint().port());
  s.accept();
  s.sweep();
  s.io_thread = std::thread([&s] { s.io.run(); });
}

WebServer::~WebServer() {
  impl_->io.stop();
  if (impl_->io_thread.joinable()) impl_->io_thread.join();
  impl_->workers.join();  // a tour still searching ends within its budget
  impl_->feeds.clear();
}

std::uint16_t WebServer::port() const { return impl_->acceptor.local_endpoint().port(); }

WebServerStats WebServer::stats() const {
  return {impl_->browsers,      impl_->browsers_total, impl_->messages, impl_->refused, impl_->refused_access,
          impl_->tours_refused, impl_->feeds.size(),   impl_->evicted,  impl_->unread};
}

}  // namespace ispars::web
