#include "reply_cache.hpp"

namespace ispars::server {

ReplyCache::Admission ReplyCache::admit(const std::string& client, std::uint64_t seq, msg::Reply& reply) {
  std::lock_guard lock(mutex_);
  auto it = clients_.find(client);
  if (it == clients_.end()) {
    if (clients_.size() >= max_clients_) {
      clients_.erase(lru_.back());
      lru_.pop_back();
    }
    lru_.push_front(client);
    it = clients_.emplace(client, Client{{}, lru_.begin()}).first;
  } else {
    lru_.splice(lru_.begin(), lru_, it->second.lru);
  }
  auto& replies = it->second.replies;
  if (const auto r = replies.find(seq); r != replies.end()) {
    if (!r->second) return Admission::in_progress;
    reply = *r->second;
    return Admission::answered;
  }
  replies.emplace(seq, std::nullopt);
  while (replies.size() > per_client_) replies.erase(replies.begin());
  return Admission::new_request;
}

void ReplyCache::complete(const std::string& client, std::uint64_t seq, const msg::Reply& reply) {
  std::lock_guard lock(mutex_);
  const auto it = clients_.find(client);
  if (it == clients_.end()) return;
  const auto r = it->second.replies.find(seq);
  if (r == it->second.replies.end()) return;
  // Snapshot chunks are large and reading one again is harmless: not kept; a retry re-reads it.
  if (reply.body()._d() == msg::SNAPSHOT) {
    it->second.replies.erase(r);
    return;
  }
  r->second = reply;
}

void ReplyCache::forget(const std::string& client, std::uint64_t seq) {
  std::lock_guard lock(mutex_);
  const auto it = clients_.find(client);
  if (it == clients_.end()) return;
  const auto r = it->second.replies.find(seq);
  if (r != it->second.replies.end() && !r->second) it->second.replies.erase(r);
}

}  // namespace ispars::server
