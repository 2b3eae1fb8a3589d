#pragma once
// The daemon's per-client reply writers. Each client that sends a request gets a publisher in its
// own reply partition (wire::reply_partition of its transport identity) with a reply writer and a
// tour-progress writer, so a reply reaches the reader of its requester and no other: other
// clients' readers never match it, and get no bytes. Routes are made on a client's first reply
// (never inside a DDS callback: creating a writer there deadlocks with DDS's receive locks) and
// bounded in number: past the bound, the least recently used route whose reader has gone is
// released first, then the least recently used of all.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/Topic.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <mutex>
#include <shared_mutex>
#include <string>

#include "ispars.h"

namespace ispars::server {

/// Writers for one client's replies and tour progress, in that client's partition.
struct ReplyRoute {
  eprosima::fastdds::dds::Publisher* publisher = nullptr;
  eprosima::fastdds::dds::DataWriter* replies = nullptr;
  eprosima::fastdds::dds::DataWriter* progress = nullptr;
  std::uint64_t last_used = 0;  // a tick of ReplyRoutes, for least-recently-used release
};

/// The routes, one per client identity; safe to use from many threads.
class ReplyRoutes {
 public:
  /// At most this many clients hold a route at once (a reply writer each).
  static constexpr std::size_t kDefaultMaxRoutes = 256;

  /// `matched` is the listener told when a route's reply writer matches or loses its reader.
  ReplyRoutes(eprosima::fastdds::dds::DomainParticipant* participant, eprosima::fastdds::dds::Topic* reply_topic,
              eprosima::fastdds::dds::Topic* progress_topic, eprosima::fastdds::dds::DataWriterListener* matched,
              std::size_t max_routes = kDefaultMaxRoutes);

  /// Makes `client`'s route if it has none (releasing one past the bound). False when DDS refused
  /// to create it (logged).
  bool open(const std::string& client);
  /// Whether `client` has a route now.
  [[nodiscard]] bool has(const std::string& client) const;
  /// Writes `reply` on its client's route (opened on demand). False when it could not be written.
  bool write_reply(const msg::Reply& reply);
  /// Writes `progress` on its client's route, if the client has one (progress is advisory).
  void write_progress(const msg::TourProgress& progress);
  /// Notes that `client`'s reply reader left: its route is released first when room is needed.
  void reader_left(const std::string& client);
  [[nodiscard]] std::size_t size() const;

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_;
  eprosima::fastdds::dds::Topic* reply_topic_;
  eprosima::fastdds::dds::Topic* progress_topic_;
  eprosima::fastdds::dds::DataWriterListener* matched_;
  std::size_t max_routes_;
  mutable std::shared_mutex mutex_;  // shared: writes; exclusive: opening and releasing routes
  std::map<std::string, ReplyRoute> routes_;
  std::mutex gone_mutex_;  // apart from mutex_: reader_left runs in DDS's listener thread
  std::map<std::string, bool> gone_;  // clients whose reader left (released first)
  std::mutex tick_mutex_;
  std::uint64_t tick_ = 0;

  void touch(ReplyRoute& route);
  void release_one();  // with mutex_ held exclusively
  void release(std::map<std::string, ReplyRoute>::iterator it);
};

}  // namespace ispars::server
