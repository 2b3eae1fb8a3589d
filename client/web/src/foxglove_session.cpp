// The Foxglove WebSocket protocol (foxglove.websocket.v1, github.com/foxglove/ws-protocol) at
// /ws?scene=NAME, for Foxglove's 3D panel: a client that offers that subprotocol is told the
// server's info, then one channel, /ispars/NAME/roadmap, of foxglove.SceneUpdate JSON; once it
// subscribes it gets the whole roadmap, then what each replica change adds (SceneFeed,
// record::SceneUpdateCursor), as binary message frames. Everything else a client may send is
// answered with a status message naming it; the viewer's limits on queued bytes hold here too.

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <optional>

#include "websocket_peer.hpp"

namespace ispars::web {
namespace {

using Server = WebServer::Impl;
constexpr const char* kSubprotocol = "foxglove.websocket.v1";
constexpr std::uint32_t kRoadmapChannel = 1;

std::string status_op(int level, const std::string& message) {
  return nlohmann::json{{"op", "status"}, {"level", level}, {"message", message}}.dump();
}

// A messageData frame: opcode 1, the subscription id (u32) and a timestamp (u64, ns), little-endian.
std::string message_frame(std::uint32_t subscription, const std::string& payload) {
  const std::uint64_t ns = record::now_ns();
  std::string frame(1, '\x01');
  for (int i = 0; i < 4; ++i) frame.push_back(static_cast<char>((subscription >> (8 * i)) & 0xff));
  for (int i = 0; i < 8; ++i) frame.push_back(static_cast<char>((ns >> (8 * i)) & 0xff));
  return frame + payload;
}

class FoxgloveSession final : public WebSocketPeer {
 public:
  FoxgloveSession(tcp::socket socket, Server* server, std::shared_ptr<Server::Slot> slot)
      : WebSocketPeer(std::move(socket), server, std::move(slot)) {}

  std::shared_ptr<FoxgloveSession> self() { return std::static_pointer_cast<FoxgloveSession>(shared_from_this()); }

  void run(http::request<http::string_body> request, std::string scene) {
    scene_ = std::move(scene);
    set_timeouts();
    ws_.set_option(websocket::stream_base::decorator(
        [](websocket::response_type& res) { res.set(http::field::sec_websocket_protocol, kSubprotocol); }));
    ws_.async_accept(request, [self = self()](beast::error_code ec) {
      if (!ec) self->opened();
    });
  }

 private:
  void opened() {
    count();
    read();
    send(nlohmann::json{{"op", "serverInfo"},
                        {"name", "ispars-web"},
                        {"capabilities", nlohmann::json::array()},
                        {"supportedEncodings", nlohmann::json::array()},
                        {"metadata", nlohmann::json::object()}}
             .dump(),
         false);
    if (!valid_scene_name(scene_)) {
      return send(status_op(2, "scene: '" + scene_ + "' is not a scene name (1-64 of A-Za-z0-9_-.)"));
    }
    follow();
  }

  // Follows the scene, then advertises its channel; until a daemon holds it, says why once and
  // asks again every 2 s (as the viewer's page does).
  void follow() {
    if (closed()) return;
    net::post(server_->workers, [self = self()] {
      std::shared_ptr<SceneFeed> feed;
      std::string why;
      try {
        feed = self->server_->feeds.get(self->scene_);
      } catch (const std::exception& e) {
        why = e.what();
      }
      net::post(self->ws_.get_executor(), [self, feed, why] {
        if (feed) return self->advertise(feed);
        if (why != self->follow_error_)
          self->send(status_op(1, "cannot follow scene '" + self->scene_ + "' yet: " + why));
        self->follow_error_ = why;
        self->timer_.expires_after(std::chrono::seconds(2));
        self->timer_.async_wait([self](beast::error_code ec) {
          if (!ec) self->follow();
        });
      });
    });
  }

  void advertise(std::shared_ptr<SceneFeed> feed) {
    feed_ = std::move(feed);
    const nlohmann::json channel{{"id", kRoadmapChannel},
                                 {"topic", "/ispars/" + scene_ + "/roadmap"},
                                 {"encoding", "json"},
                                 {"schemaName", "foxglove.SceneUpdate"},
                                 {"schema", record::scene_update_schema()},
                                 {"schemaEncoding", "jsonschema"}};
    send(nlohmann::json{{"op", "advertise"}, {"channels", nlohmann::json::array({channel})}}.dump());
    tick();
  }

  void read() {
    ws_.async_read(buffer_, [self = self()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      const bool text = self->ws_.got_text();
      const std::string message = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      if (text) {
        self->on_message(message);
      } else {
        self->send(status_op(2, "binary messages: this server advertises no client channels"));
      }
      self->read();
    });
  }

  void on_message(const std::string& text) {
    const nlohmann::json m = nlohmann::json::parse(text, nullptr);
    if (m.is_discarded() || !m.is_object() || !m.contains("op") || !m["op"].is_string()) {
      return send(status_op(2, "request: not a JSON object with an op"));
    }
    const std::string op = m["op"].get<std::string>();
    if (op == "subscribe" && m.contains("subscriptions") && m["subscriptions"].is_array()) {
      for (const auto& s : m["subscriptions"]) {
        if (!s.is_object() || !s.value("id", nlohmann::json()).is_number_unsigned() ||
            s.value("channelId", nlohmann::json()) != kRoadmapChannel) {
          send(status_op(2, "subscribe: " + s.dump().substr(0, 200) + " is not {id, channelId: 1}"));
          continue;
        }
        subscription_ = s["id"].get<std::uint32_t>();
        restart_ = true;  // a new subscription gets the whole roadmap first (tick resets the cursor)
      }
      return;
    }
    if (op == "unsubscribe" && m.contains("subscriptionIds") && m["subscriptionIds"].is_array()) {
      for (const auto& id : m["subscriptionIds"]) {
        if (subscription_ && id == *subscription_) subscription_.reset();
      }
      return;
    }
    send(status_op(2, "op: '" + op.substr(0, 64) + "' is not supported here (subscribe, unsubscribe)"));
  }

  // The feed's next update for this client, made on a worker, every 200 ms while subscribed.
  void tick() override {
    if (closed()) return;
    if (!subscription_ || congested()) {
      return schedule_tick();
    }
    const std::uint32_t subscription = *subscription_;
    // Here, on the I/O thread, no tick's worker holds the cursor (the next tick is scheduled only
    // once the last one's worker is done).
    if (std::exchange(restart_, false)) cursor_ = record::SceneUpdateCursor{};
    net::post(server_->workers, [self = self(), subscription] {
      std::optional<std::string> update;
      try {
        update = self->feed_->scene_update_for(self->cursor_);
      } catch (const std::exception& e) {
        spdlog::warn("ispars-web: a Foxglove update of scene {} failed: {}", self->scene_, e.what());
      }
      net::post(self->ws_.get_executor(), [self, subscription, update = std::move(update)] {
        if (update && self->subscription_ == subscription) self->send(message_frame(subscription, *update), true);
        self->schedule_tick();
      });
    });
  }

  beast::flat_buffer buffer_;
  std::string scene_;
  std::shared_ptr<SceneFeed> feed_;
  record::SceneUpdateCursor cursor_;  // a worker's while a tick runs (one at a time)
  std::optional<std::uint32_t> subscription_;
  bool restart_ = false;  // a subscribe came: the cursor starts again at the next tick
  std::string follow_error_;
};

}  // namespace

bool offers_foxglove(const http::request<http::string_body>& request) {
  const std::string offered(request[http::field::sec_websocket_protocol]);
  return offered.find(kSubprotocol) != std::string::npos;
}

void start_foxglove_websocket(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot,
                              http::request<http::string_body> request, std::string scene) {
  std::make_shared<FoxgloveSession>(std::move(socket), server, std::move(slot))
      ->run(std::move(request), std::move(scene));
}

}  // namespace ispars::web
