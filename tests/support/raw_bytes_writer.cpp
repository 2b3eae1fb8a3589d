#include "support/raw_bytes_writer.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "support/eventually.hpp"
#include "support/raw_bytes_type.hpp"

namespace ispars::test {
namespace fdds = eprosima::fastdds::dds;

class RawBytesWriter::Impl {
 public:
  Impl(int domain, const std::string& security, const std::string& topic_name, const std::string& type_name)
      : participant({domain, "", "ispars", "raw bytes", security}), type(new RawBytesType(type_name, /*keyed=*/true)) {
    fdds::DomainParticipant* p = participant.get();
    fdds::Topic* topic = wire::find_or_create_topic(p, type, topic_name.c_str());
    fdds::Publisher* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (!pub) throw std::runtime_error("raw bytes: no publisher");
    writer = pub->create_datawriter(topic, wire::request_reply_writer_qos());
    if (!writer) throw std::runtime_error("raw bytes: no writer");
  }
  ~Impl() { participant->delete_contained_entities(); }
  wire::Participant participant;
  fdds::TypeSupport type;
  fdds::DataWriter* writer = nullptr;
};

RawBytesWriter::RawBytesWriter(int domain, const std::string& security, const std::string& topic,
                               const std::string& type_name)
    : impl_(std::make_unique<Impl>(domain, security, topic, type_name)) {}
RawBytesWriter::~RawBytesWriter() = default;

bool RawBytesWriter::wait_matched(int seconds) {
  return eventually(
      [&] {
        fdds::PublicationMatchedStatus status;
        impl_->writer->get_publication_matched_status(status);
        return status.current_count > 0;
      },
      std::chrono::seconds(seconds), "the writer matches a reader", std::chrono::milliseconds(10));
}

bool RawBytesWriter::write(const std::string& bytes) {
  std::string copy = bytes;
  return impl_->writer->write(&copy);
}

}  // namespace ispars::test
