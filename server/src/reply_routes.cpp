#include "reply_routes.hpp"

#include <spdlog/spdlog.h>

#include "ispars/wire/topics.hpp"

namespace ispars::server {
namespace fdds = eprosima::fastdds::dds;

ReplyRoutes::ReplyRoutes(fdds::DomainParticipant* participant, fdds::Topic* reply_topic, fdds::Topic* progress_topic,
                         fdds::DataWriterListener* matched, std::size_t max_routes)
    : participant_(participant),
      reply_topic_(reply_topic),
      progress_topic_(progress_topic),
      matched_(matched),
      max_routes_(max_routes < 1 ? 1 : max_routes) {}

void ReplyRoutes::touch(ReplyRoute& route) {
  std::lock_guard lock(tick_mutex_);
  route.last_used = ++tick_;
}

bool ReplyRoutes::open(const std::string& client) {
  {
    std::shared_lock lock(mutex_);
    if (const auto it = routes_.find(client); it != routes_.end()) {
      touch(it->second);
      return true;
    }
  }
  std::unique_lock lock(mutex_);
  if (routes_.count(client) > 0) return true;
  while (routes_.size() >= max_routes_) release_one();
  ReplyRoute route;
  route.publisher = participant_->create_publisher(wire::reply_publisher_qos(client));
  if (route.publisher != nullptr) {
    route.replies = route.publisher->create_datawriter(reply_topic_, wire::request_reply_writer_qos(), matched_,
                                                       fdds::StatusMask::publication_matched());
    route.progress = route.publisher->create_datawriter(progress_topic_, wire::request_reply_writer_qos());
  }
  if (route.publisher == nullptr || route.replies == nullptr || route.progress == nullptr) {
    spdlog::error("cannot create the reply writers for client {}", client);
    if (route.publisher != nullptr) {
      route.publisher->delete_contained_entities();
      participant_->delete_publisher(route.publisher);
    }
    return false;
  }
  touch(route);
  routes_.emplace(client, route);
  std::lock_guard gone(gone_mutex_);
  gone_.erase(client);
  return true;
}

bool ReplyRoutes::write_reply(const msg::Reply& reply) {
  const std::string client = reply.client_id().to_string();
  if (!open(client)) return false;
  std::shared_lock lock(mutex_);
  const auto it = routes_.find(client);
  if (it == routes_.end()) return false;  // released in between: the client retries
  msg::Reply copy = reply;
  return it->second.replies->write(&copy);
}

void ReplyRoutes::write_progress(const msg::TourProgress& progress) {
  std::shared_lock lock(mutex_);
  const auto it = routes_.find(progress.client_id().to_string());
  if (it == routes_.end()) return;
  msg::TourProgress copy = progress;
  it->second.progress->write(&copy);
}

void ReplyRoutes::reader_left(const std::string& client) {
  std::lock_guard lock(gone_mutex_);
  gone_[client] = true;
}

bool ReplyRoutes::has(const std::string& client) const {
  std::shared_lock lock(mutex_);
  return routes_.count(client) > 0;
}

std::size_t ReplyRoutes::size() const {
  std::shared_lock lock(mutex_);
  return routes_.size();
}

void ReplyRoutes::release_one() {
  std::map<std::string, bool> gone;
  {
    std::lock_guard lock(gone_mutex_);
    gone = gone_;
  }
  auto victim = routes_.end();
  for (const auto& [client, flag] : gone) {
    const auto it = routes_.find(client);
    if (it != routes_.end() && (victim == routes_.end() || it->second.last_used < victim->second.last_used)) victim = it;
  }
  if (victim == routes_.end()) {
    for (auto it = routes_.begin(); it != routes_.end(); ++it) {
      if (victim == routes_.end() || it->second.last_used < victim->second.last_used) victim = it;
    }
  }
  if (victim != routes_.end()) release(victim);
}

void ReplyRoutes::release(std::map<std::string, ReplyRoute>::iterator it) {
  spdlog::debug("releasing the reply route of client {}", it->first);
  it->second.replies->set_listener(nullptr);
  it->second.publisher->delete_contained_entities();
  participant_->delete_publisher(it->second.publisher);
  {
    std::lock_guard lock(gone_mutex_);
    gone_.erase(it->first);
  }
  routes_.erase(it);
}

}  // namespace ispars::server
