#include "ispars/wire/topics.hpp"

namespace ispars::wire {
namespace fdds = eprosima::fastdds::dds;

namespace {

// Unlimited is spelled 0, on all three fields together (Fast DDS 2.9).
template <class Qos>
void unlimited_instances(Qos& qos) {
  qos.resource_limits().max_samples = 0;
  qos.resource_limits().max_instances = 0;
  qos.resource_limits().max_samples_per_instance = 0;
}

}  // namespace

fdds::DataWriterQos request_reply_writer_qos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 64;
  unlimited_instances(qos);
  return qos;
}

fdds::DataReaderQos request_reply_reader_qos() {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::VOLATILE_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 64;
  unlimited_instances(qos);
  return qos;
}

fdds::DataWriterQos updates_writer_qos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = kUpdatesKept;
  qos.publish_mode().kind = fdds::ASYNCHRONOUS_PUBLISH_MODE;
  unlimited_instances(qos);
  return qos;
}

fdds::DataReaderQos updates_reader_qos() {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 256;
  unlimited_instances(qos);
  return qos;
}

fdds::DataWriterQos state_writer_qos() {
  fdds::DataWriterQos qos = fdds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 1;
  unlimited_instances(qos);
  return qos;
}

fdds::DataReaderQos state_reader_qos() {
  fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
  qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 1;
  unlimited_instances(qos);
  return qos;
}

}  // namespace ispars::wire
