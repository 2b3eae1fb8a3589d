#include "client_link.hpp"

#include "ispars/wire/identity.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::client {
namespace fdds = eprosima::fastdds::dds;

ClientLink::ClientLink(const wire::ParticipantOptions& options, const ClientListeners& listeners)
    : participant_(options),
      listeners_(listeners),
      query_type_(new wire::SafeType<msg::QueryRequestPubSubType>()),
      change_type_(new wire::SafeType<msg::ChangeRequestPubSubType>()),
      reply_type_(new wire::SafeType<msg::ReplyPubSubType>()),
      status_type_(new wire::SafeType<msg::SceneStatusPubSubType>()),
      daemon_type_(new wire::SafeType<msg::DaemonInfoPubSubType>()),
      progress_type_(new wire::SafeType<msg::TourProgressPubSubType>()) {
  fdds::DomainParticipant* p = participant_.get();
  fdds::Topic* query_topic = wire::find_or_create_topic(p, query_type_, wire::kQueryTopic);
  change_topic_ = wire::find_or_create_topic(p, change_type_, wire::kChangeTopic);
  fdds::Topic* reply_topic = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
  fdds::Topic* status_topic = wire::find_or_create_topic(p, status_type_, wire::kStatusTopic);
  fdds::Topic* daemon_topic = wire::find_or_create_topic(p, daemon_type_, wire::kDaemonsTopic);
  id_ = wire::identity_of(participant_->guid().guidPrefix);
  publisher_ = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  // Replies and tour progress arrive in this client's own partition: no other client's reader
  // matches the daemon's writer for it, and this one matches no one else's.
  reply_subscriber_ = p->create_subscriber(wire::reply_subscriber_qos(id_));
  if (!publisher_ || !subscriber_ || !reply_subscriber_) {
    throw std::runtime_error("cannot create the DDS publisher and subscribers");
  }
  reply_reader_ = reply_subscriber_->create_datareader(reply_topic, wire::request_reply_reader_qos(), listeners.replies,
                                                       fdds::StatusMask::data_available());
  queries_ = publisher_->create_datawriter(query_topic, wire::request_reply_writer_qos());
  status_reader_ = subscriber_->create_datareader(status_topic, wire::state_reader_qos(), listeners.statuses);
  daemon_reader_ = subscriber_->create_datareader(daemon_topic, wire::state_reader_qos(), listeners.daemons);
  if (!reply_reader_ || !queries_ || !status_reader_ || !daemon_reader_) {
    throw std::runtime_error("cannot create the client's DDS readers and writers");
  }
}

ClientLink::~ClientLink() {
  {
    std::lock_guard lock(lazy_mutex_);
    if (progress_reader_) progress_reader_->set_listener(nullptr);
  }
  reply_reader_->set_listener(nullptr);
  status_reader_->set_listener(nullptr);
  daemon_reader_->set_listener(nullptr);
  // Delete the readers now, while the listeners they point to still exist.
  participant_->delete_contained_entities();
}

fdds::DataWriter* ClientLink::changes() {
  std::lock_guard lock(lazy_mutex_);
  if (changes_ == nullptr && !changes_refused_) {
    changes_ = publisher_->create_datawriter(change_topic_, wire::request_reply_writer_qos());
    changes_refused_ = changes_ == nullptr;
  }
  return changes_;
}

void ClientLink::ensure_progress_reader() {
  std::lock_guard lock(lazy_mutex_);
  if (progress_reader_) return;
  fdds::Topic* topic = wire::find_or_create_topic(participant_.get(), progress_type_, wire::kTourProgressTopic);
  progress_reader_ = reply_subscriber_->create_datareader(topic, wire::request_reply_reader_qos(), listeners_.progress,
                                                          fdds::StatusMask::data_available());
}

bool ClientLink::has_progress_reader() const {
  std::lock_guard lock(lazy_mutex_);
  return progress_reader_ != nullptr;
}

}  // namespace ispars::client
