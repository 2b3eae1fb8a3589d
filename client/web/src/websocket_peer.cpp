#include "websocket_peer.hpp"

namespace ispars::web {

WebSocketPeer::WebSocketPeer(tcp::socket socket, WebServer::Impl* server, std::shared_ptr<WebServer::Impl::Slot> slot)
    : ws_(std::move(socket)), timer_(ws_.get_executor()), server_(server), slot_(std::move(slot)) {}

void WebSocketPeer::set_timeouts() {
  // A browser answers pings by itself: a peer silent for a minute, pings unanswered, is gone.
  auto timeout = websocket::stream_base::timeout::suggested(beast::role_type::server);
  timeout.idle_timeout = std::chrono::seconds(60);
  timeout.keep_alive_pings = true;
  ws_.set_option(timeout);
  ws_.read_message_max(64 * 1024);
}

void WebSocketPeer::count() {
  ++server_->browsers;
  ++server_->browsers_total;
  counted_ = true;
}

bool WebSocketPeer::congested() const {
  return queue_.size() >= server_->options.max_queued_messages || queued_bytes_ >= server_->options.max_queued_bytes;
}

void WebSocketPeer::send(std::string message, bool binary) {
  if (closed_) return;
  // Updates wait at max_queued_bytes (congested); only replies to what the peer sends grow the
  // queue past it, so a peer that sends and does not read is closed at twice it.
  if (!queue_.empty() && queued_bytes_ + message.size() > 2 * server_->options.max_queued_bytes) {
    ++server_->unread;
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
    return close();
  }
  queued_bytes_ += message.size();
  queue_.push_back({std::make_shared<std::string>(std::move(message)), binary});
  if (queue_.size() == 1) write();
}

void WebSocketPeer::write() {
  // The handler holds the message: close() may clear the queue while the write is in flight.
  const auto [message, binary] = queue_.front();
  ws_.binary(binary);
  ws_.async_write(net::buffer(*message), [self = shared_from_this(), message](beast::error_code ec, std::size_t) {
    // The peer went away mid-stream (or was closed): this session ends, the others go on.
    if (ec || self->closed_) return self->close();
    ++self->server_->messages;
    self->queued_bytes_ -= message->size();
    self->queue_.pop_front();
    if (!self->queue_.empty()) self->write();
  });
}

void WebSocketPeer::schedule_tick() {
  if (closed_) return;
  timer_.expires_after(std::chrono::milliseconds(200));
  timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
    if (!ec) self->tick();
  });
}

void WebSocketPeer::close() {
  if (closed_) return;
  closed_ = true;
  timer_.cancel();
  queue_.clear();
  queued_bytes_ = 0;
  if (counted_) --server_->browsers;
}

}  // namespace ispars::web
