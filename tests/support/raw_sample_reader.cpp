#include "support/raw_sample_reader.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <stdexcept>

#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "support/raw_bytes_type.hpp"

namespace ispars::test {
namespace fdds = eprosima::fastdds::dds;

class RawSampleReader::Impl {
 public:
  Impl(int domain, const std::string& topic_name, const std::string& type_name)
      : participant({domain, "", "ispars", "raw sample reader", ""}), type(new RawBytesType(type_name, false)) {
    fdds::DomainParticipant* p = participant.get();
    fdds::Topic* topic = wire::find_or_create_topic(p, type, topic_name.c_str());
    fdds::Subscriber* sub = wire::created(p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT), "subscriber");
    fdds::DataReaderQos qos = fdds::DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = fdds::RELIABLE_RELIABILITY_QOS;
    qos.durability().kind = fdds::TRANSIENT_LOCAL_DURABILITY_QOS;
    qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 64;
    reader = wire::created(sub->create_datareader(topic, qos), "reader on " + topic_name);
  }
  ~Impl() { participant->delete_contained_entities(); }
  wire::Participant participant;
  fdds::TypeSupport type;
  fdds::DataReader* reader = nullptr;
};

RawSampleReader::RawSampleReader(int domain, const std::string& topic, const std::string& type_name)
    : impl_(std::make_unique<Impl>(domain, topic, type_name)) {}
RawSampleReader::~RawSampleReader() = default;

std::vector<std::string> RawSampleReader::take() {
  std::vector<std::string> out;
  std::string bytes;
  fdds::SampleInfo info;
  while (impl_->reader->take_next_sample(&bytes, &info) == ReturnCode_t::RETCODE_OK) {
    if (info.valid_data) out.push_back(bytes);
  }
  return out;
}

bool RawSampleReader::matched() const {
  fdds::SubscriptionMatchedStatus status;
  impl_->reader->get_subscription_matched_status(status);
  return status.current_count > 0;
}

}  // namespace ispars::test
