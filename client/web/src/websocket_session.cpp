// The viewer's WebSocket side: one session per browser, streaming a scene's roadmap as it grows,
// its status, and tours on request.

#include <spdlog/spdlog.h>

#include "websocket_peer.hpp"

namespace ispars::web {
namespace {

using Server = WebServer::Impl;

class WsSession final : public WebSocketPeer {
 public:
  WsSession(tcp::socket socket, Server* server, std::shared_ptr<Server::Slot> slot)
      : WebSocketPeer(std::move(socket), server, std::move(slot)) {}

  std::shared_ptr<WsSession> self() { return std::static_pointer_cast<WsSession>(shared_from_this()); }

  void run(http::request<http::string_body> request) {
    const std::string target(request.target());
    scene_ = query_value(target, "scene");
    set_timeouts();
    ws_.async_accept(request, [self = self()](beast::error_code ec) {
      if (!ec) self->opened();
    });
  }

 private:
  void opened() {
    count();
    read();
    if (!valid_scene_name(scene_)) {
      send(error_message("scene: '" + scene_ + "' is not a scene name (1-64 of A-Za-z0-9_-.)"));
      return;
    }
    follow();
  }

  // Follows the scene. When that fails (no daemon holds it yet, or the gateway has not yet
  // discovered one) the page is told why, once per reason, and the gateway asks again every 2 s
  // while the page stays open: a page opened before its scene is loaded draws it once it is.
  void follow() {
    if (closed()) return;
    net::post(server_->workers, [self = self()] {
      try {
        auto feed = self->server_->feeds.get(self->scene_);
        net::post(self->ws_.get_executor(), [self, feed] {
          self->feed_ = feed;
          self->tick();
        });
      } catch (const std::exception& e) {
        std::string why = e.what();
        std::string m = error_message(why);
        net::post(self->ws_.get_executor(), [self, why = std::move(why), m = std::move(m)]() mutable {
          if (m != self->follow_error_) {
            spdlog::info("ispars-web: cannot follow scene {} yet (asking again every 2 s): {}", self->scene_, why);
            self->send(m);
          }
          self->follow_error_ = std::move(m);
          self->timer_.expires_after(std::chrono::seconds(2));
          self->timer_.async_wait([self](beast::error_code ec) {
            if (!ec) self->follow();
          });
        });
      }
    });
  }

  void read() {
    ws_.async_read(buffer_, [self = self()](beast::error_code ec, std::size_t) {
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
    if (m["type"] == "tasks") return send_tasks();
    if (m["type"] != "tour") {
      return send(error_message("request: type: '" + m["type"].dump() + "' is not tour or tasks"));
    }
    std::string task;  // a task's tour: its POIs seen from the root's component
    if (m.contains("task")) {
      if (!m["task"].is_string() || !valid_scene_name(m["task"].get<std::string>())) {
        return send(error_message("tour: task: not a task name (1-64 of A-Za-z0-9_-.)"));
      }
      task = m["task"].get<std::string>();
    }
    if (m.contains("budget") && !m["budget"].is_number()) return send(error_message("tour: budget: not a number"));
    const double budget = m.value("budget", 2.0);
    if (!(budget >= 0.1 && budget <= server_->options.tour_budget_max)) {
      return send(
          error_message(fmt::format("tour: budget: must be 0.1..{} seconds", server_->options.tour_budget_max)));
    }
    if (tour_running_) return send(error_message("tour: this page's last tour is still searching"));
    if (!feed_) return send(error_message("tour: the scene is not followed yet"));
    // Every page's tours take the daemon's tour slots: the gateway runs at most max_tours at once.
    if (server_->tours >= server_->options.max_tours) {
      ++server_->tours_refused;
      return send(
          error_message(fmt::format("tour: the gateway runs {} tours at once already (its limit, --max-tours); "
                                    "ask again when one ends",
                                    server_->options.max_tours)));
    }
    ++server_->tours;
    tour_running_ = true;
    net::post(server_->workers, [self = self(), budget, task] {
      std::string reply;
      try {
        const auto r = task.empty() ? self->server_->client.tour(self->scene_, budget, 1, {})
                                    : self->server_->client.task_tour(self->scene_, task, budget, 1);
        // The viewer draws the flown tour, the path a drone flies; the walk's length goes with it.
        const client::Tour& t = r.tour;
        const auto& drawn = t.flown_path.empty() ? t.waypoints : t.flown_path;
        nlohmann::json positions = nlohmann::json::array();
        for (const auto& p : drawn) positions.push_back({p.x(), p.y(), p.z()});
        reply = nlohmann::json{{"type", "tour"},
                               {"cost", t.flown_path.empty() ? t.cost : t.flown_cost},
                               {"roadmap_cost", t.cost},
                               {"covered", r.tour.covered},
                               {"targets", r.tour.target_count},
                               {"task", task},
                               {"valid", r.tour.valid},
                               {"positions", positions}}
                    .dump();
      } catch (const std::exception& e) {
        reply = error_message(std::string("tour: ") + e.what());
      }
      net::post(self->ws_.get_executor(), [self, reply] {
        --self->server_->tours;
        self->tour_running_ = false;
        self->send(reply);
      });
    });
  }

  // The scene's tasks, asked of the daemon on a worker.
  void send_tasks() {
    if (!feed_) return send(error_message("tasks: the scene is not followed yet"));
    if (tasks_running_) {
      tasks_again_ = true;  // one ask at a time; one more after it, which sees any change since
      return;
    }
    tasks_running_ = true;
    net::post(server_->workers, [self = self()] {
      std::string reply;
      try {
        reply = self->feed_->tasks_message();
      } catch (const std::exception& e) {
        reply = error_message(std::string("tasks: ") + e.what());
      }
      net::post(self->ws_.get_executor(), [self, reply = std::move(reply)]() mutable {
        self->tasks_running_ = false;
        self->send(std::move(reply));
        if (std::exchange(self->tasks_again_, false)) self->send_tasks();
      });
    });
  }

  // The feed's next messages for this browser, made on a worker (copying the roadmap and
  // encoding batches must not hold up the I/O thread that serves every browser).
  void tick() override {
    if (closed()) return;
    // A slow browser: nothing more is queued until its socket drains; it then gets everything new
    // at once (the cursor only moves when messages are queued).
    if (congested()) {
      return schedule_tick();
    }
    net::post(server_->workers, [self = self()] {
      std::vector<std::string> out;
      try {
        out = self->feed_->updates_for(self->cursor_);
      } catch (const std::exception& e) {
        out = {error_message(e.what())};
      }
      net::post(self->ws_.get_executor(), [self, out = std::move(out)]() mutable {
        for (std::string& m : out) self->send(std::move(m));
        self->schedule_tick();
      });
    });
  }

  beast::flat_buffer buffer_;
  std::string scene_;
  std::shared_ptr<SceneFeed> feed_;
  ViewerCursor cursor_;
  bool tour_running_ = false;
  bool tasks_running_ = false;
  bool tasks_again_ = false;
  std::string follow_error_;  // the last reason the scene could not be followed, sent once
};

}  // namespace

void start_websocket(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot,
                     http::request<http::string_body> request) {
  std::make_shared<WsSession>(std::move(socket), server, std::move(slot))->run(std::move(request));
}

}  // namespace ispars::web
