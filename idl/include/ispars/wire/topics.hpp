#pragma once
// The service's topic names and the QoS each endpoint uses, in one place so daemon and clients
// always agree.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/publisher/qos/PublisherQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/subscriber/qos/SubscriberQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <stdexcept>
#include <string>

namespace ispars::wire {

/// Requests that read (list, stats, path, snapshot, verify, tour).
inline constexpr const char* kQueryTopic = "ispars/query";
/// Requests that change what a daemon holds (load, unload, build, extend, cancel, drop).
inline constexpr const char* kChangeTopic = "ispars/change";
inline constexpr const char* kReplyTopic = "ispars/reply";
inline constexpr const char* kUpdatesTopic = "ispars/updates";
inline constexpr const char* kStatusTopic = "ispars/status";
inline constexpr const char* kDaemonsTopic = "ispars/daemons";
inline constexpr const char* kTourProgressTopic = "ispars/tour_progress";
/// Each scene's inspection tasks, as the daemon holding it publishes them for the fleet.
inline constexpr const char* kTasksTopic = "ispars/tasks";

/// The DDS partition a client's replies and tour progress travel in: "ispars.client." followed by
/// the client's identity (its participant's GUID prefix, 24 hex digits). The daemon writes each
/// client's replies in that client's partition only, so no other reader matches them and no other
/// client gets their bytes. Under DDS Security the permissions let each subject subscribe only to
/// the partitions of its own certificate (the prefix's first 6 bytes are bound to it).
[[nodiscard]] std::string reply_partition(const std::string& identity);
/// A publisher (daemon) or subscriber (client) QoS in `identity`'s reply partition.
[[nodiscard]] eprosima::fastdds::dds::PublisherQos reply_publisher_qos(const std::string& identity);
[[nodiscard]] eprosima::fastdds::dds::SubscriberQos reply_subscriber_qos(const std::string& identity);

/// `entity` as a Fast DDS create_* call returned it; throws std::runtime_error("cannot create the
/// <what>") when the call created none.
template <class T>
T* created(T* entity, const std::string& what) {
  if (entity == nullptr) throw std::runtime_error("cannot create the " + what);
  return entity;
}

/// The topic `name` of `type` on `participant`: registers the type, then returns the topic the
/// participant already has under that name or creates it. Throws std::runtime_error naming the
/// topic when it can be neither found nor created. The one way daemon, clients and benchmarks set up a topic.
eprosima::fastdds::dds::Topic* find_or_create_topic(eprosima::fastdds::dds::DomainParticipant* participant,
                                                    eprosima::fastdds::dds::TypeSupport& type, const char* name);

/// Requests and replies: reliable, volatile, a deep history per client (keyed by client id),
/// no limit on the number of clients.
eprosima::fastdds::dds::DataWriterQos request_reply_writer_qos();
eprosima::fastdds::dds::DataReaderQos request_reply_reader_qos();
/// The daemon's reply and progress writers: request_reply_writer_qos with a heartbeat every
/// 20 ms instead of 200 (a reader acknowledges on a heartbeat, and a route is ready on the first
/// acknowledgement; a writer sends them only while something is unacknowledged).
eprosima::fastdds::dds::DataWriterQos route_writer_qos();

/// Batches of roadmap updates kept per scene for late joiners.
inline constexpr int kUpdatesKept = 64;

/// Roadmap updates: reliable, transient-local with the last kUpdatesKept batches per scene (a late
/// joiner's snapshot may be a few commits old: it finds the batches after it here), published
/// asynchronously so a slow subscriber never blocks the build (it sees a version gap and resyncs).
eprosima::fastdds::dds::DataWriterQos updates_writer_qos();
eprosima::fastdds::dds::DataReaderQos updates_reader_qos();

/// Scene status and daemon announcements: reliable, transient-local, the last sample per key,
/// so a late joiner sees the current state at once.
eprosima::fastdds::dds::DataWriterQos state_writer_qos();
eprosima::fastdds::dds::DataReaderQos state_reader_qos();

}  // namespace ispars::wire
