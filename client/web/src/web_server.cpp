// The viewer's HTTP side: the listener, one request per connection (the page, the scene list,
// meshes), and the hand-over of WebSocket upgrades to websocket_session.cpp.

#include "web_server_impl.hpp"

namespace ispars::web {

bool valid_scene_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name[0] == '.') return false;
  return std::all_of(name.begin(), name.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; });
}

std::string error_message(const std::string& what) { return nlohmann::json{{"type", "error"}, {"message", what}}.dump(); }

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

namespace {

using Server = WebServer::Impl;

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
      start_websocket(stream_.release_socket(), server_, slot_, std::move(request));
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

std::shared_ptr<SceneFeed> WebServer::Impl::feed_for(const std::string& scene) {
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
    body = it == kFiles.end() ? "not found\n" : name + " is missing from the web root " + options.web_root.string() + "\n";
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
