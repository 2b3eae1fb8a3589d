#pragma once
// A replica's DDS side: the update reader of its scene on the client's participant of the moment
// (a ParticipantUser: made again when the client rejoins the domain), and the bounded queue its
// listener fills. DDS delivers updates on its receive thread, which must never block (a snapshot
// request made there would wait for a reply that same thread has to deliver): the listener only
// queues, and the replica's own thread takes what it queued.

#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>

#include "ispars/client/client.hpp"
#include "ispars/client/replica.hpp"
#include "isparsPubSubTypes.h"

namespace eprosima::fastdds::dds {
class ContentFilteredTopic;
class DataReader;
class Subscriber;
}  // namespace eprosima::fastdds::dds

namespace ispars::client {

/// The update reader of one scene and its queue; safe from the DDS thread and the replica's.
class ReplicaInbox final : public eprosima::fastdds::dds::DataReaderListener, public ParticipantUser {
 public:
  /// Subscribes through `client` (attach(); throws when the reader cannot be made). `limits`
  /// must have been checked (checked_limits).
  ReplicaInbox(Client& client, std::string scene, const ReplicaLimits& limits);
  ~ReplicaInbox() override;
  ReplicaInbox(const ReplicaInbox&) = delete;
  ReplicaInbox& operator=(const ReplicaInbox&) = delete;

  void attach(wire::Participant& participant) override;
  void detach(wire::Participant& participant) override;
  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override;
  void on_subscription_matched(eprosima::fastdds::dds::DataReader* reader,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override;

  /// Waits until the reader has matched a writer, `timeout` has passed or stop() was called;
  /// whether it has matched one (false while detached).
  bool wait_matched(std::chrono::milliseconds timeout);
  /// The batches queued, once there is one or `timeout` has passed or stop() was called.
  [[nodiscard]] std::deque<msg::UpdateBatch> take(std::chrono::milliseconds timeout);
  /// Waits `timeout` unless stop() is called; false once it was.
  bool pause(std::chrono::milliseconds timeout);
  void stop();
  [[nodiscard]] bool stopping();
  /// Whether the reader was made on a new participant (batches may be missing) since the last ask.
  [[nodiscard]] bool take_rejoined();
  [[nodiscard]] std::size_t dropped();
  [[nodiscard]] std::size_t other_scenes() const { return other_scenes_.load(); }

 private:
  // With mutex_ held. Queues `batch`, then drops the oldest queued batches past the limits (never
  // the newest): the next batch applied then shows a gap, and the replica resyncs.
  void queue(msg::UpdateBatch batch);

  Client& client_;
  const std::string scene_;
  const ReplicaLimits limits_;
  eprosima::fastdds::dds::TypeSupport type_;

  std::mutex mutex_;  // the reader, the queue and stopping
  std::condition_variable wake_;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::DataReader* reader_ = nullptr;
  eprosima::fastdds::dds::ContentFilteredTopic* filtered_ = nullptr;
  std::atomic<std::size_t> other_scenes_{0};  // batches of other scenes that reached the reader
  std::size_t attached_ = 0;                  // participants attached to so far
  std::int32_t matched_writers_ = 0;          // the reader's, as its listener last heard
  bool rejoined_ = false;                     // attached to a new participant since the last look
  std::deque<msg::UpdateBatch> inbox_;
  std::size_t inbox_bytes_ = 0;
  std::size_t dropped_ = 0;  // batches dropped from a full queue
  bool stopping_ = false;
};

/// `limits`, or throws std::invalid_argument naming the first out of its range.
[[nodiscard]] ReplicaLimits checked_limits(const ReplicaLimits& limits);

}  // namespace ispars::client
