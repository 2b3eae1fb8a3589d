#include "ispars/wire/topics.hpp"

#include <stdexcept>
#include <string>
#include <type_traits>

namespace ispars::wire {
namespace fdds = eprosima::fastdds::dds;

namespace {

// Reliable, KEEP_LAST `depth` per instance, no limit on instances (Fast DDS 2.9 spells unlimited
// 0, on all three resource limits together).
template <class Qos>
Qos reliable(Qos qos, fdds::DurabilityQosPolicyKind durability, int depth) {
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = durability;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
  qos.resource_limits().max_samples = 0;
  qos.resource_limits().max_instances = 0;
  qos.resource_limits().max_samples_per_instance = 0;
  if constexpr (std::is_same_v<Qos, fdds::DataWriterQos>) {
    // A sample lost on the way (a full socket buffer under load, say) is repaired at the
    // writer's next heartbeat: every 200 ms rather than Fast DDS's 3 s.
    qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 200'000'000);
  }
  return qos;
}

}  // namespace

std::string reply_partition(const std::string& identity) { return "ispars.client." + identity; }

fdds::PublisherQos reply_publisher_qos(const std::string& identity) {
  fdds::PublisherQos qos = fdds::PUBLISHER_QOS_DEFAULT;
  qos.partition().push_back(reply_partition(identity).c_str());
  return qos;
}

fdds::SubscriberQos reply_subscriber_qos(const std::string& identity) {
  fdds::SubscriberQos qos = fdds::SUBSCRIBER_QOS_DEFAULT;
  qos.partition().push_back(reply_partition(identity).c_str());
  return qos;
}

fdds::Topic* find_or_create_topic(fdds::DomainParticipant* participant, fdds::TypeSupport& type, const char* name) {
  // A second registration of the type on one participant (two replicas, say) is not an error
  // here: if the type is not there, creating the topic fails below and says so.
  (void)type.register_type(participant);
  if (auto* existing = dynamic_cast<fdds::Topic*>(participant->lookup_topicdescription(name))) return existing;
  fdds::Topic* topic = participant->create_topic(name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw std::runtime_error(std::string("cannot create topic ") + name);
  return topic;
}

fdds::DataWriterQos request_reply_writer_qos() {
  return reliable(fdds::DATAWRITER_QOS_DEFAULT, fdds::VOLATILE_DURABILITY_QOS, 64);
}

fdds::DataWriterQos route_writer_qos() {
  fdds::DataWriterQos qos = request_reply_writer_qos();
  qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 20'000'000);
  return qos;
}

fdds::DataReaderQos request_reply_reader_qos() {
  return reliable(fdds::DATAREADER_QOS_DEFAULT, fdds::VOLATILE_DURABILITY_QOS, 64);
}

fdds::DataWriterQos updates_writer_qos() {
  fdds::DataWriterQos qos = reliable(fdds::DATAWRITER_QOS_DEFAULT, fdds::TRANSIENT_LOCAL_DURABILITY_QOS, kUpdatesKept);
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  // No writer-side filtering: Fast DDS 2.9.1 sizes a sample's fragments before it adds the
  // filter's information to their inline QoS, so a batch past one datagram would never reach a
  // filtered reader in another process (tests/wire/test_scene_filter.cpp). Each replica's reader
  // filters on its own side, before any sample reaches the application.
  qos.writer_resource_limits().reader_filters_allocation.initial = 0;
  qos.writer_resource_limits().reader_filters_allocation.maximum = 0;
  return qos;
}

fdds::DataReaderQos updates_reader_qos() {
  return reliable(fdds::DATAREADER_QOS_DEFAULT, fdds::TRANSIENT_LOCAL_DURABILITY_QOS, 256);
}

fdds::DataWriterQos state_writer_qos() {
  return reliable(fdds::DATAWRITER_QOS_DEFAULT, fdds::TRANSIENT_LOCAL_DURABILITY_QOS, 1);
}

fdds::DataReaderQos state_reader_qos() {
  return reliable(fdds::DATAREADER_QOS_DEFAULT, fdds::TRANSIENT_LOCAL_DURABILITY_QOS, 1);
}

}  // namespace ispars::wire
