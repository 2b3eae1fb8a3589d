#pragma once
// De-duplication of retried requests: a client that times out resends the same (client id,
// sequence number); the daemon answers it from here instead of running the request again.

#include <cstdint>
#include <list>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "ispars.h"

namespace ispars::server {

/// Recent replies per client, bounded in clients and per client, so a retry is never run twice.
/// A request in progress is never evicted (the bounds may be passed by at most the requests the
/// daemon's lanes hold).
class ReplyCache {
 public:
  /// What to do with an incoming request.
  enum class Admission { new_request, in_progress, answered };

  explicit ReplyCache(std::size_t clients = 1024, std::size_t per_client = 128)
      : max_clients_(clients), per_client_(per_client) {}

  /// Registers the request; for an answered one, `reply` receives the cached reply.
  Admission admit(const std::string& client, std::uint64_t seq, msg::Reply& reply);
  /// Stores the reply of a request admitted as new.
  void complete(const std::string& client, std::uint64_t seq, const msg::Reply& reply);
  /// Forgets a request admitted as new that was not run (refused as busy): its retry is new.
  void forget(const std::string& client, std::uint64_t seq);

 private:
  struct Client {
    std::map<std::uint64_t, std::optional<msg::Reply>> replies;  // nullopt: in progress
    std::list<std::string>::iterator lru;
  };
  void evict_a_client();  // under mutex_
  std::mutex mutex_;
  std::map<std::string, Client> clients_;
  std::list<std::string> lru_;  // most recent first
  std::size_t max_clients_;
  std::size_t per_client_;
};

}  // namespace ispars::server
