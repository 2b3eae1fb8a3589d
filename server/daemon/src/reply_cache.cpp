#include "ispars/server/reply_cache.hpp"

#include <algorithm>
#include <iterator>

namespace ispars::server {

ReplyCache::Admission ReplyCache::admit(const std::string& client, std::uint64_t seq, msg::Reply& reply) {
  std::lock_guard lock(mutex_);
  auto it = clients_.find(client);
  if (it == clients_.end()) {
    if (clients_.size() >= max_clients_) evict_a_client();
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
  // The oldest answered replies go first. A request in progress is never forgotten (its retry
  // would run it twice): those are bounded by the daemon's lanes, not here.
  for (auto r = replies.begin(); replies.size() > per_client_ && r != replies.end();) {
    r = r->second ? replies.erase(r) : std::next(r);
  }
  return Admission::new_request;
}

void ReplyCache::evict_a_client() {
  // The least recent client with nothing in progress; none: the cache grows past its bound for
  // now (by at most the requests the lanes hold).
  for (auto l = lru_.rbegin(); l != lru_.rend(); ++l) {
    const auto c = clients_.find(*l);
    const bool in_progress =
        std::any_of(c->second.replies.begin(), c->second.replies.end(), [](const auto& r) { return !r.second; });
    if (in_progress) continue;
    clients_.erase(c);
    lru_.erase(std::next(l).base());
    return;
  }
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
