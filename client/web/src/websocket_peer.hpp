#pragma once
// What every WebSocket peer of the gateway shares, the viewer's page and a Foxglove client alike:
// the socket, its timer, and an outgoing queue bounded by the gateway's limits (a peer that
// sends and never reads is closed at twice max_queued_bytes), counted among the browsers.

#include <deque>
#include <memory>
#include <string>

#include "web_server_impl.hpp"

namespace ispars::web {

class WebSocketPeer : public std::enable_shared_from_this<WebSocketPeer> {
 public:
  WebSocketPeer(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot);
  virtual ~WebSocketPeer() = default;
  WebSocketPeer(const WebSocketPeer&) = delete;
  WebSocketPeer& operator=(const WebSocketPeer&) = delete;

 protected:
  /// The server's timeouts (60 s idle, pings kept up) and a 64 KiB bound on what the peer sends.
  void set_timeouts();
  /// Counts the accepted peer among the gateway's browsers (uncounted by close()).
  void count();
  /// Queues `message` for the peer, as a text or a binary frame.
  void send(std::string message, bool binary = false);
  /// Ends the session: the timer is cancelled and the queue dropped.
  void close();
  [[nodiscard]] bool closed() const { return closed_; }
  /// Whether the queue is at the gateway's bound (updates then wait for it to drain).
  [[nodiscard]] bool congested() const;
  /// The session's next look at its feed.
  virtual void tick() = 0;
  /// Calls tick() after 200 ms, unless the session closes meanwhile.
  void schedule_tick();

  websocket::stream<beast::tcp_stream> ws_;
  net::steady_timer timer_;
  WebServer::Impl* server_;
  std::shared_ptr<WebServer::Impl::Slot> slot_;

 private:
  void write();
  std::deque<std::pair<std::shared_ptr<std::string>, bool>> queue_;  // message, binary
  std::size_t queued_bytes_ = 0;                                     // the bytes in queue_
  bool closed_ = false;
  bool counted_ = false;
};

}  // namespace ispars::web
