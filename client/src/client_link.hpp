#pragma once
// One DDS participant of a client and every entity the client made on it (private to
// client/src): made when the client starts, and made again when it rejoins the domain under DDS
// Security (client_rejoin.cpp). The listeners belong to the client and outlive every link.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <mutex>
#include <string>

#include "ispars/client/client.hpp"
#include "ispars/wire/participant.hpp"

namespace ispars::client {

/// The client's listeners, one per reader kind.
struct ClientListeners {
  eprosima::fastdds::dds::DataReaderListener* replies = nullptr;
  eprosima::fastdds::dds::DataReaderListener* statuses = nullptr;
  eprosima::fastdds::dds::DataReaderListener* daemons = nullptr;
  eprosima::fastdds::dds::DataReaderListener* progress = nullptr;
};

/// See the file comment. Throws std::runtime_error when the participant or an entity cannot be
/// made. Its queries are safe from many threads while the link lives.
class ClientLink {
 public:
  ClientLink(const wire::ParticipantOptions& options, const ClientListeners& listeners);
  ~ClientLink();
  ClientLink(const ClientLink&) = delete;
  ClientLink& operator=(const ClientLink&) = delete;

  [[nodiscard]] wire::Participant& participant() { return participant_; }
  /// The participant's identity (wire::identity_of its GUID prefix).
  [[nodiscard]] const std::string& id() const { return id_; }
  [[nodiscard]] eprosima::fastdds::dds::DataWriter* queries() const { return queries_; }
  /// The change writer, made on first use: under DDS Security a viewer's permissions refuse it,
  /// and such a client still queries and follows updates. Null when refused.
  [[nodiscard]] eprosima::fastdds::dds::DataWriter* changes();
  /// Subscribes to tour progress (in this client's reply partition) on first use.
  void ensure_progress_reader();
  [[nodiscard]] bool has_progress_reader() const;

 private:
  wire::Participant participant_;
  ClientListeners listeners_;
  std::string id_;
  eprosima::fastdds::dds::TypeSupport query_type_, change_type_, reply_type_, status_type_, daemon_type_,
      progress_type_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::Subscriber* reply_subscriber_ = nullptr;  // in this client's reply partition
  eprosima::fastdds::dds::DataReader* reply_reader_ = nullptr;
  eprosima::fastdds::dds::DataWriter* queries_ = nullptr;
  eprosima::fastdds::dds::Topic* change_topic_ = nullptr;
  eprosima::fastdds::dds::DataReader* status_reader_ = nullptr;
  eprosima::fastdds::dds::DataReader* daemon_reader_ = nullptr;
  mutable std::mutex lazy_mutex_;  // the entities made on first use
  eprosima::fastdds::dds::DataWriter* changes_ = nullptr;
  bool changes_refused_ = false;
  eprosima::fastdds::dds::DataReader* progress_reader_ = nullptr;
};

}  // namespace ispars::client
