#include "ispars/wire/identity.hpp"

#include <cstdio>

namespace ispars::wire {

std::string identity_of(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix) {
  std::string out;
  out.reserve(2 * eprosima::fastrtps::rtps::GuidPrefix_t::size);
  for (const auto byte : prefix.value) {
    char hex[3];
    std::snprintf(hex, sizeof(hex), "%02x", static_cast<unsigned>(byte));
    out += hex;
  }
  return out;
}

std::string sender_identity(const eprosima::fastdds::dds::SampleInfo& info) {
  return identity_of(info.sample_identity.writer_guid().guidPrefix);
}

std::string identity_of(const eprosima::fastrtps::rtps::InstanceHandle_t& handle) {
  return identity_of(eprosima::fastrtps::rtps::iHandle2GUID(handle).guidPrefix);
}

}  // namespace ispars::wire
