#pragma once
// The daemon's per-client reply writers. Each client gets a publisher in its own reply partition
// (wire::reply_partition of its transport identity) with a reply writer and a tour-progress
// writer, so a reply reaches the reader of its requester and no other: other clients' readers
// never match it, and get no bytes.
//
// A route is opened as soon as the daemon discovers the client's reply reader (or on its first
// request, whichever comes first), and becomes ready only once that reader has acknowledged a
// route-open reply (request_seq 0) written after the writer matched it: a reader of any vendor
// that has acknowledged a sample knows the writer, so the replies after it are delivered. (A
// reader that has not yet linked the new writer drops a sample and then acknowledges it as
// already seen, so a first reply written on a bare match can be lost without the writer
// learning: measured with Cyclone DDS, 11 of 40 fresh clients.)
//
// Routes are opened and released only on the sender thread (service()), never inside a DDS
// callback (creating or deleting a writer there deadlocks with DDS's receive locks). A route is
// released when its reader leaves, when it never matched a reader within kUnmatchedLifetime, and
// past the bound (the least recently used first).

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <shared_mutex>
#include <string>

#include "ispars.h"

namespace ispars::server {

/// Writers for one client's replies and tour progress, in that client's partition.
struct ReplyRoute {
  enum class Phase { opened, marked, ready };
  eprosima::fastdds::dds::Publisher* publisher = nullptr;
  eprosima::fastdds::dds::DataWriter* replies = nullptr;
  eprosima::fastdds::dds::DataWriter* progress = nullptr;
  Phase phase = Phase::opened;
  std::chrono::steady_clock::time_point opened_at;
  std::uint64_t last_used = 0;  // a tick of ReplyRoutes, for least-recently-used release
};

/// The routes, one per client identity. want() and forget() are safe from any thread, DDS's
/// callbacks included; service() runs on one thread (the sender's); the rest from any thread.
class ReplyRoutes {
 public:
  using Clock = std::chrono::steady_clock;
  /// At most this many clients hold a route at once (a reply writer each).
  static constexpr std::size_t kDefaultMaxRoutes = 256;
  /// A route whose writer never matched a reader in this long is released.
  static constexpr Clock::duration kUnmatchedLifetime = std::chrono::seconds(10);

  /// `matched` is the listener told when a route's reply writer matches or loses its reader;
  /// `server_id` signs the route-open replies.
  ReplyRoutes(eprosima::fastdds::dds::DomainParticipant* participant, eprosima::fastdds::dds::Topic* reply_topic,
              eprosima::fastdds::dds::Topic* progress_topic, eprosima::fastdds::dds::DataWriterListener* matched,
              std::string server_id, std::size_t max_routes = kDefaultMaxRoutes);

  /// Asks for `client`'s route (opened by the next service()).
  void want(const std::string& client);
  /// Asks to release `client`'s route (its reader left).
  void forget(const std::string& client);
  /// Whether want() or forget() left work for service().
  [[nodiscard]] bool has_work() const;
  /// Opens and releases the routes asked for, in order, and moves each route's handshake on.
  /// True while some handshake waits for its reader (call again soon).
  bool service(Clock::time_point now = Clock::now());

  /// Whether `client` has a route now, and whether its reader has acknowledged it.
  [[nodiscard]] bool has(const std::string& client) const;
  [[nodiscard]] bool ready(const std::string& client) const;
  /// Writes `reply` on its client's route. False when the client has no route, or DDS refused.
  bool write_reply(const msg::Reply& reply);
  /// Writes `progress` on its client's route; asks for the route when there is none (progress
  /// is advisory: the next one goes out on it).
  void write_progress(const msg::TourProgress& progress);
  /// Routes held, and routes ready.
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] std::size_t ready_count() const;

 private:
  using Routes = std::map<std::string, ReplyRoute>;
  eprosima::fastdds::dds::DomainParticipant* participant_;
  eprosima::fastdds::dds::Topic* reply_topic_;
  eprosima::fastdds::dds::Topic* progress_topic_;
  eprosima::fastdds::dds::DataWriterListener* matched_;
  std::string server_id_;
  std::size_t max_routes_;
  mutable std::shared_mutex mutex_;  // shared: writes and queries; exclusive: service()
  Routes routes_;
  mutable std::mutex asked_mutex_;                  // apart from mutex_: want and forget run in DDS's threads
  std::deque<std::pair<std::string, bool>> asked_;  // (client, open?) in the order asked
  std::mutex tick_mutex_;
  std::uint64_t tick_ = 0;

  void touch(ReplyRoute& route);
  void open(const std::string& client, Clock::time_point now);  // with mutex_ held exclusively
  void release(Routes::iterator it);                            // with mutex_ held exclusively
  void release_one();                                           // the least recently used
  bool advance(const std::string& client, ReplyRoute& route);   // true: still waiting
};

}  // namespace ispars::server
