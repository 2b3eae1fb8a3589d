#pragma once
// A DDS type of any name whose samples are their serialized bytes, as they travel (the
// encapsulation header included): what a test writes that no typed writer would, and what it
// reads to hand to a decoder of another code base.

#include <fastdds/dds/topic/TopicDataType.hpp>

#include <algorithm>
#include <cstring>
#include <functional>
#include <string>

namespace ispars::test {

class RawBytesType final : public eprosima::fastdds::dds::TopicDataType {
 public:
  /// `keyed`: one instance per distinct leading 16 bytes (so written samples are not all one
  /// instance's history); else unkeyed, as ROS 2's types are.
  RawBytesType(const std::string& type_name, bool keyed) {
    setName(type_name.c_str());
    m_typeSize = 1 << 20;
    m_isGetKeyDefined = keyed;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto* bytes = static_cast<const std::string*>(data);
    if (bytes->size() > payload->max_size) return false;
    std::memcpy(payload->data, bytes->data(), bytes->size());
    payload->length = static_cast<std::uint32_t>(bytes->size());
    payload->encapsulation = CDR_LE;
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    static_cast<std::string*>(data)->assign(reinterpret_cast<const char*>(payload->data), payload->length);
    return true;
  }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<const std::string*>(data)->size()); };
  }
  void* createData() override { return new std::string(); }
  void deleteData(void* data) override { delete static_cast<std::string*>(data); }
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool) override {
    if (!m_isGetKeyDefined) return false;
    const auto* bytes = static_cast<const std::string*>(data);
    std::memset(handle->value, 0, 16);
    std::memcpy(handle->value, bytes->data(), std::min<std::size_t>(16, bytes->size()));
    return true;
  }
};

}  // namespace ispars::test
