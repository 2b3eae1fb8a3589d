#pragma once
// A bare DDS peer on the service's topics, for tests that must send what the client library never
// would (a request of another protocol version) or pose as a daemon (an announcement of another
// version). Its client id is its reply reader's GUID, as a client's is.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "ispars.h"

namespace ispars::test {

class RawPeer {
 public:
  /// Joins `domain` with the localhost-only settings.
  explicit RawPeer(int domain);
  ~RawPeer();
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;

  /// Sends `request` as given except for its client id (this peer's), and waits for the reply to
  /// that id and sequence number; nullopt after `timeout`.
  std::optional<msg::Reply> send(msg::QueryRequest request, std::chrono::milliseconds timeout);
  /// Publishes `info` on the announcement topic, as a daemon does; kept while this peer lives.
  void announce(const msg::DaemonInfo& info);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::test
