#include "ispars/server/reply_routes.hpp"

#include <spdlog/spdlog.h>

#include <utility>

#include "ispars/wire/topics.hpp"

namespace ispars::server {
namespace fdds = eprosima::fastdds::dds;

ReplyRoutes::ReplyRoutes(fdds::DomainParticipant* participant, fdds::Topic* reply_topic, fdds::Topic* progress_topic,
                         fdds::DataWriterListener* matched, std::string server_id, std::size_t max_routes)
    : participant_(participant),
      reply_topic_(reply_topic),
      progress_topic_(progress_topic),
      matched_(matched),
      server_id_(std::move(server_id)),
      max_routes_(max_routes < 1 ? 1 : max_routes) {}

void ReplyRoutes::touch(ReplyRoute& route) {
  std::lock_guard lock(tick_mutex_);
  route.last_used = ++tick_;
}

void ReplyRoutes::want(const std::string& client) {
  std::lock_guard lock(asked_mutex_);
  asked_.emplace_back(client, true);
}

void ReplyRoutes::forget(const std::string& client) {
  std::lock_guard lock(asked_mutex_);
  asked_.emplace_back(client, false);
}

bool ReplyRoutes::has_work() const {
  std::lock_guard lock(asked_mutex_);
  return !asked_.empty();
}

bool ReplyRoutes::service(Clock::time_point now) {
  std::deque<std::pair<std::string, bool>> asked;
  {
    std::lock_guard lock(asked_mutex_);
    asked.swap(asked_);
  }
  std::unique_lock lock(mutex_);
  for (const auto& [client, open_it] : asked) {
    const auto it = routes_.find(client);
    if (open_it && it == routes_.end()) open(client, now);
    if (!open_it && it != routes_.end()) release(it);
  }
  bool waiting = false;
  for (auto it = routes_.begin(); it != routes_.end();) {
    if (it->second.phase == ReplyRoute::Phase::opened && now - it->second.opened_at >= kUnmatchedLifetime) {
      const auto next = std::next(it);
      spdlog::debug("the reply route of client {} matched no reader in {} s", it->first,
                    std::chrono::duration_cast<std::chrono::seconds>(kUnmatchedLifetime).count());
      release(it);
      it = next;
      continue;
    }
    waiting = advance(it->first, it->second) || waiting;
    ++it;
  }
  return waiting;
}

bool ReplyRoutes::advance(const std::string& client, ReplyRoute& route) {
  if (route.phase == ReplyRoute::Phase::ready) return false;
  if (route.phase == ReplyRoute::Phase::opened) {
    fdds::PublicationMatchedStatus matched;
    if (route.replies->get_publication_matched_status(matched) != ReturnCode_t::RETCODE_OK ||
        matched.current_count < 1) {
      return true;
    }
    // Written after the match, so the reader is owed it: its acknowledgement says it knows the
    // writer. Clients ignore a reply to request_seq 0 (no request has it).
    msg::Reply marker;
    marker.client_id(client);
    marker.request_seq(0);
    marker.server_id(server_id_);
    marker.protocol(msg::PROTOCOL_VERSION);
    marker.ok(true);
    marker.message("route open");
    marker.body().list_scenes(msg::SceneList{});
    if (!route.replies->write(&marker)) return true;
    route.phase = ReplyRoute::Phase::marked;
  }
  if (route.replies->wait_for_acknowledgments(eprosima::fastrtps::Duration_t(0, 0)) != ReturnCode_t::RETCODE_OK) {
    return true;
  }
  route.phase = ReplyRoute::Phase::ready;
  spdlog::debug("the reply route of client {} is ready", client);
  return false;
}

void ReplyRoutes::open(const std::string& client, Clock::time_point now) {
  while (routes_.size() >= max_routes_) release_one();
  ReplyRoute route;
  route.opened_at = now;
  route.publisher = participant_->create_publisher(wire::reply_publisher_qos(client));
  if (route.publisher != nullptr) {
    route.replies = route.publisher->create_datawriter(reply_topic_, wire::route_writer_qos(), matched_,
                                                       fdds::StatusMask::publication_matched());
    route.progress = route.publisher->create_datawriter(progress_topic_, wire::route_writer_qos());
  }
  if (route.publisher == nullptr || route.replies == nullptr || route.progress == nullptr) {
    spdlog::error("cannot create the reply writers for client {}", client);
    if (route.publisher != nullptr) {
      route.publisher->delete_contained_entities();
      participant_->delete_publisher(route.publisher);
    }
    return;
  }
  touch(route);
  routes_.emplace(client, route);
  spdlog::debug("opened a reply route for client {} ({} held)", client, routes_.size());
}

bool ReplyRoutes::write_reply(const msg::Reply& reply) {
  std::shared_lock lock(mutex_);
  const auto it = routes_.find(reply.client_id().to_string());
  if (it == routes_.end()) return false;
  touch(it->second);
  msg::Reply copy = reply;
  return it->second.replies->write(&copy);
}

void ReplyRoutes::write_progress(const msg::TourProgress& progress) {
  {
    std::shared_lock lock(mutex_);
    const auto it = routes_.find(progress.client_id().to_string());
    if (it != routes_.end()) {
      msg::TourProgress copy = progress;
      it->second.progress->write(&copy);
      return;
    }
  }
  want(progress.client_id().to_string());
}

bool ReplyRoutes::has(const std::string& client) const {
  std::shared_lock lock(mutex_);
  return routes_.count(client) > 0;
}

bool ReplyRoutes::ready(const std::string& client) const {
  std::shared_lock lock(mutex_);
  const auto it = routes_.find(client);
  return it != routes_.end() && it->second.phase == ReplyRoute::Phase::ready;
}

std::size_t ReplyRoutes::size() const {
  std::shared_lock lock(mutex_);
  return routes_.size();
}

std::size_t ReplyRoutes::ready_count() const {
  std::shared_lock lock(mutex_);
  std::size_t n = 0;
  for (const auto& [client, route] : routes_) n += route.phase == ReplyRoute::Phase::ready ? 1 : 0;
  return n;
}

void ReplyRoutes::release_one() {
  auto victim = routes_.end();
  for (auto it = routes_.begin(); it != routes_.end(); ++it) {
    if (victim == routes_.end() || it->second.last_used < victim->second.last_used) victim = it;
  }
  if (victim != routes_.end()) release(victim);
}

void ReplyRoutes::release(Routes::iterator it) {
  spdlog::debug("releasing the reply route of client {}", it->first);
  it->second.replies->set_listener(nullptr);
  it->second.publisher->delete_contained_entities();
  participant_->delete_publisher(it->second.publisher);
  routes_.erase(it);
}

}  // namespace ispars::server
