#pragma once
// The daemon's DDS probe: a writer and a reader of its own on topic "ispars/probe", in a partition
// named after this participant alone ("ispars.probe.IDENTITY"), so that no other participant's
// reader matches and no one else receives a sample. ping() writes one; heard() says when the last
// one came back. isparsd delivers nothing inside its process (main.cpp): a sample heard came
// through the daemon's own sockets and receive threads, which is what /healthz checks with it.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <atomic>
#include <chrono>
#include <string>

#include "ispars.h"

namespace ispars::server {

/// See the file comment. Made on a participant that has `type` (msg::DaemonInfo) registered.
class SelfProbe final : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using Clock = std::chrono::steady_clock;
  SelfProbe(eprosima::fastdds::dds::DomainParticipant* participant, eprosima::fastdds::dds::TypeSupport& type,
            const std::string& identity);
  /// Writes one probe sample.
  void ping();
  /// When a probe sample last came back (its creation time until the first).
  [[nodiscard]] Clock::time_point heard() const { return Clock::time_point(Clock::duration(heard_.load())); }
  /// Detaches the listener (before the participant deletes the entities).
  void detach();

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;

 private:
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  msg::DaemonInfo sample_;
  std::atomic<Clock::rep> heard_{Clock::now().time_since_epoch().count()};
};

}  // namespace ispars::server
