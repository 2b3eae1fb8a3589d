#include "support/raw_bytes_writer.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>

#include "ispars/wire/participant.hpp"
#include "ispars/wire/topics.hpp"
#include "support/eventually.hpp"

namespace ispars::test {
namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

// The request type's name and key kind, with a payload of whatever bytes are given.
class BytesType final : public fdds::TopicDataType {
 public:
  explicit BytesType(const std::string& type_name) {
    setName(type_name.c_str());
    m_typeSize = 1 << 20;
    m_isGetKeyDefined = true;
  }
  bool serialize(void* data, rtps::SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<const std::string*>(data);
    if (bytes->size() > payload->max_size) return false;
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = static_cast<std::uint32_t>(bytes->size());
    payload->encapsulation = CDR_LE;
    return true;
  }
  bool deserialize(rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<const std::string*>(data)->size()); };
  }
  void* createData() override { return new std::string(); }
  void deleteData(void* data) override { delete static_cast<std::string*>(data); }
  bool getKey(void* data, rtps::InstanceHandle_t* handle, bool) override {
    // One instance per distinct leading bytes, so samples are not all one instance's history.
    const auto* bytes = static_cast<const std::string*>(data);
    std::memset(handle->value, 0, 16);
    std::memcpy(handle->value, bytes->data(), std::min<std::size_t>(16, bytes->size()));
    return true;
  }
};

}  // namespace

class RawBytesWriter::Impl {
 public:
  Impl(int domain, const std::string& security, const std::string& topic_name, const std::string& type_name)
      : participant({domain, "", "ispars", "raw bytes", security}), type(new BytesType(type_name)) {
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
