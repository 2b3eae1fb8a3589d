#pragma once
// Who sent a sample, as the transport says: the RTPS GUID prefix of the sender's participant,
// never a field the sender fills in. Every entity of one client (its query and change writers,
// its reply reader) shares it, so a daemon answers a request to the reader of the same prefix.
// The prefix is plain RTPS (12 bytes), so any vendor's client can compute its own.

#include <fastdds/rtps/common/InstanceHandle.h>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/rtps/common/GuidPrefix_t.hpp>

#include <string>

namespace ispars::wire {

/// The prefix as 24 lowercase hex digits.
[[nodiscard]] std::string identity_of(const eprosima::fastrtps::rtps::GuidPrefix_t& prefix);
/// The identity of the participant that wrote the sample `info` describes.
[[nodiscard]] std::string sender_identity(const eprosima::fastdds::dds::SampleInfo& info);
/// The identity of the participant an entity handle (a matched reader or writer) belongs to.
[[nodiscard]] std::string identity_of(const eprosima::fastrtps::rtps::InstanceHandle_t& handle);

}  // namespace ispars::wire
