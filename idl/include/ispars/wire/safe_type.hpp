#pragma once
// Type support that never lets a malformed sample end the process. fastddsgen's deserialize
// catches only "not enough data"; a bad encapsulation header or another Fast CDR error throws
// out of take_next_sample into the reader's listener thread, and the process terminates. Here
// every such error makes deserialize return false, and Fast DDS drops that one sample; the drop
// is logged as a Fast DDS warning (the daemon routes those to its log).

#include <fastdds/rtps/common/SerializedPayload.h>

#include <exception>

namespace ispars::wire {

/// Logs a dropped malformed sample of `type_name` (a Fast DDS warning, category ISPARS).
void report_malformed_sample(const char* type_name, const char* what);

/// `Generated` (a fastddsgen PubSubType) whose deserialize refuses what it cannot read.
template <class Generated>
class SafeType final : public Generated {
 public:
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    try {
      return Generated::deserialize(payload, data);
    } catch (const std::exception& e) {
      report_malformed_sample(this->getName(), e.what());
    } catch (...) {
      report_malformed_sample(this->getName(), "unknown error");
    }
    return false;
  }
};

}  // namespace ispars::wire
