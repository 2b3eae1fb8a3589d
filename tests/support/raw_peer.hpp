#pragma once
// A bare DDS peer on the service's topics, for tests that must send what the client library never
// would (a request of another protocol version) or pose as a daemon (an announcement of another
// version). Its identity is its participant's GUID prefix, as a client's is.

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ispars.h"

namespace ispars::test {

class RawPeer {
 public:
  /// Joins `domain` with the localhost-only settings (as the DDS Security identity `security`
  /// unless empty). With `read_replies` false its reply reader is made only by
  /// open_reply_reader(), as a client slow to match would.
  explicit RawPeer(int domain, const std::string& security = "", bool read_replies = true);
  ~RawPeer();
  RawPeer(const RawPeer&) = delete;
  RawPeer& operator=(const RawPeer&) = delete;

  /// Sends `request` as given except for its client id (this peer's), and waits for the reply to
  /// that id and sequence number; nullopt after `timeout`.
  std::optional<msg::Reply> send(msg::QueryRequest request, std::chrono::milliseconds timeout);
  /// Writes `request` exactly as given (its client id too: a forged one is the point of some
  /// tests), without waiting for a reply (waits, up to `timeout`, for the daemon to match).
  /// False when nothing matched.
  bool post(msg::QueryRequest request, std::chrono::milliseconds timeout = std::chrono::seconds(30));
  /// The same for a change request (on the change topic).
  std::optional<msg::Reply> send(msg::ChangeRequest request, std::chrono::milliseconds timeout);
  bool post(msg::ChangeRequest request, std::chrono::milliseconds timeout = std::chrono::seconds(30));
  /// Makes the reply reader (once; a no-op when it exists).
  void open_reply_reader();
  /// Replies that arrived addressed to another client (the daemon keeps them off this peer's
  /// partition, so this stays 0).
  [[nodiscard]] std::size_t foreign_replies() const;
  /// Route-open replies (request_seq 0) received: the daemon writes one on each new route.
  [[nodiscard]] std::size_t route_opens() const;
  /// Replies received so far (to sends and posts alike), by sequence number; route-opens aside.
  [[nodiscard]] std::size_t replies_received() const;
  /// The replies received so far.
  [[nodiscard]] std::vector<msg::Reply> replies() const;
  /// This peer's identity as the daemon reads it from the transport (its GUID prefix).
  [[nodiscard]] const std::string& identity() const;
  /// Replies received to sequence number `seq` (each retry answered counts), and the latest.
  [[nodiscard]] std::size_t replies_to(std::uint64_t seq) const;
  [[nodiscard]] std::optional<msg::Reply> reply_to(std::uint64_t seq) const;
  /// Joins the updates topic as a late joiner, waits `wait`, and returns how many batches of
  /// `scene` the writers' kept history delivered.
  std::size_t kept_update_batches(const std::string& scene, std::chrono::milliseconds wait);
  /// Publishes `info` on the announcement topic, as a daemon does; kept while this peer lives.
  void announce(const msg::DaemonInfo& info);

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ispars::test
