#include "ispars/server/self_probe.hpp"

#include <spdlog/spdlog.h>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <stdexcept>

#include "ispars/wire/topics.hpp"

namespace ispars::server {
namespace fdds = eprosima::fastdds::dds;

namespace {

constexpr const char* kProbeTopic = "ispars/probe";

}  // namespace

SelfProbe::SelfProbe(fdds::DomainParticipant* participant, fdds::TypeSupport& type, const std::string& identity) {
  fdds::Topic* topic = wire::find_or_create_topic(participant, type, kProbeTopic);
  const std::string partition = "ispars.probe." + identity;
  fdds::PublisherQos pub_qos = fdds::PUBLISHER_QOS_DEFAULT;
  pub_qos.partition().push_back(partition.c_str());
  fdds::SubscriberQos sub_qos = fdds::SUBSCRIBER_QOS_DEFAULT;
  sub_qos.partition().push_back(partition.c_str());
  fdds::Publisher* pub = wire::created(participant->create_publisher(pub_qos), "DDS probe's publisher");
  fdds::Subscriber* sub = wire::created(participant->create_subscriber(sub_qos), "DDS probe's subscriber");
  // Best effort, volatile, the latest only: a lost probe is replaced by the next.
  fdds::DataWriterQos writer_qos = fdds::DATAWRITER_QOS_DEFAULT;
  writer_qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
  writer_qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  writer_qos.history().depth = 1;
  fdds::DataReaderQos reader_qos = fdds::DATAREADER_QOS_DEFAULT;
  reader_qos.reliability().kind = fdds::BEST_EFFORT_RELIABILITY_QOS;
  reader_qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  reader_qos.history().depth = 1;
  writer_ = wire::created(pub->create_datawriter(topic, writer_qos), "DDS probe's writer");
  reader_ = wire::created(sub->create_datareader(topic, reader_qos, this, fdds::StatusMask::data_available()),
                          "DDS probe's reader");
  sample_.server_id(identity.substr(0, 64));
}

void SelfProbe::ping() {
  if (!writer_->write(&sample_)) spdlog::debug("the DDS probe could not be written");
}

void SelfProbe::detach() { reader_->set_listener(nullptr); }

void SelfProbe::on_data_available(fdds::DataReader* reader) {
  msg::DaemonInfo sample;
  fdds::SampleInfo info;
  while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) {
    if (info.valid_data) heard_ = Clock::now().time_since_epoch().count();
  }
}

}  // namespace ispars::server
