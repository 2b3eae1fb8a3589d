#include "replica_inbox.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <stdexcept>
#include <utility>

#include "ispars/wire/identity.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/scene_filter.hpp"
#include "ispars/wire/topics.hpp"

namespace ispars::client {
namespace fdds = eprosima::fastdds::dds;
namespace {

std::size_t payload_bytes(const msg::UpdateBatch& b) {
  return b.order().size() + b.vertices().size() * sizeof(msg::Vertex) + b.edges().size() * sizeof(msg::Edge);
}

}  // namespace

ReplicaLimits checked_limits(const ReplicaLimits& limits) {
  if (limits.batches < 1 || limits.batches > 1'000'000) {
    throw std::invalid_argument("replica queue limit: batches must be in 1..1000000, not " +
                                std::to_string(limits.batches));
  }
  if (limits.bytes < (std::size_t{64} << 10) || limits.bytes > (std::size_t{64} << 30)) {
    throw std::invalid_argument("replica queue limit: bytes must be in 65536..68719476736, not " +
                                std::to_string(limits.bytes));
  }
  if (limits.lag < std::chrono::milliseconds(100) || limits.lag > std::chrono::hours(1)) {
    throw std::invalid_argument("replica limit: lag must be in 100..3600000 ms, not " +
                                std::to_string(limits.lag.count()));
  }
  return limits;
}

ReplicaInbox::ReplicaInbox(Client& client, std::string scene, const ReplicaLimits& limits)
    : client_(client),
      scene_(std::move(scene)),
      limits_(limits),
      type_(new wire::SafeType<msg::UpdateBatchPubSubType>()) {
  client_.add_participant_user(*this);  // attach(): throws when the reader cannot be made
}

ReplicaInbox::~ReplicaInbox() { client_.remove_participant_user(*this); }

void ReplicaInbox::attach(wire::Participant& participant) {
  fdds::DomainParticipant* p = participant.get();
  fdds::Topic* topic = wire::find_or_create_topic(p, type_, wire::kUpdatesTopic);
  // This scene's batches only (wire/scene_filter.hpp); a name of its own, as several replicas
  // may share the participant.
  static std::atomic<std::uint64_t> filters{0};
  const std::string name = std::string(wire::kUpdatesTopic) + "@" + scene_ + "#" + std::to_string(++filters);
  fdds::ContentFilteredTopic* filtered = topic ? wire::scene_filtered_topic(p, topic, name, scene_) : nullptr;
  fdds::Subscriber* subscriber = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  if (!filtered || !subscriber) {
    if (filtered) p->delete_contentfilteredtopic(filtered);
    if (subscriber) p->delete_subscriber(subscriber);
    throw std::runtime_error("cannot subscribe to roadmap updates");
  }
  fdds::DataReader* reader =
      subscriber->create_datareader(filtered, wire::updates_reader_qos(), this,
                                    fdds::StatusMask::data_available() << fdds::StatusMask::subscription_matched());
  if (!reader) {
    p->delete_subscriber(subscriber);
    p->delete_contentfilteredtopic(filtered);
    throw std::runtime_error("cannot create the update reader");
  }
  std::lock_guard lock(mutex_);
  subscriber_ = subscriber;
  reader_ = reader;
  filtered_ = filtered;
  rejoined_ = attached_ > 0;  // a new participant: batches may have been missed
  ++attached_;
  wake_.notify_all();
}

void ReplicaInbox::detach(wire::Participant& participant) {
  fdds::Subscriber* subscriber = nullptr;
  fdds::DataReader* reader = nullptr;
  fdds::ContentFilteredTopic* filtered = nullptr;
  {
    std::lock_guard lock(mutex_);
    subscriber = std::exchange(subscriber_, nullptr);
    reader = std::exchange(reader_, nullptr);
    filtered = std::exchange(filtered_, nullptr);
  }
  if (!reader) return;
  reader->set_listener(nullptr);
  {
    std::lock_guard lock(mutex_);
    matched_writers_ = 0;  // the next participant's reader matches anew
  }
  subscriber->delete_datareader(reader);
  participant->delete_subscriber(subscriber);
  participant->delete_contentfilteredtopic(filtered);
}

void ReplicaInbox::on_subscription_matched(fdds::DataReader*, const fdds::SubscriptionMatchedStatus& status) {
  {
    std::lock_guard lock(mutex_);
    matched_writers_ = status.current_count;
  }
  wake_.notify_all();
}

bool ReplicaInbox::wait_matched(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, timeout, [&] { return stopping_ || (reader_ != nullptr && matched_writers_ > 0); });
  return reader_ != nullptr && matched_writers_ > 0;
}

void ReplicaInbox::on_data_available(fdds::DataReader* reader) {
  msg::UpdateBatch batch;
  fdds::SampleInfo info;
  while (reader->take_next_sample(&batch, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data) continue;
    if (batch.scene() != scene_) {  // the filter lets none through: counted, to show it
      other_scenes_.fetch_add(1);
      continue;
    }
    // Only from the participant that announces the daemon the batch names (transport
    // identity): a forged batch never makes the replica resync.
    if (!client_.written_by_daemon(batch.server_id().to_string(), wire::sender_identity(info))) continue;
    {
      std::lock_guard lock(mutex_);
      queue(std::move(batch));
    }
    wake_.notify_all();
  }
}

void ReplicaInbox::queue(msg::UpdateBatch batch) {
  inbox_bytes_ += payload_bytes(batch);
  inbox_.push_back(std::move(batch));
  while (inbox_.size() > 1 && (inbox_.size() > limits_.batches || inbox_bytes_ > limits_.bytes)) {
    inbox_bytes_ -= payload_bytes(inbox_.front());
    inbox_.pop_front();
    ++dropped_;
  }
}

std::deque<msg::UpdateBatch> ReplicaInbox::take(std::chrono::milliseconds timeout) {
  std::deque<msg::UpdateBatch> batches;
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, timeout, [&] { return stopping_ || !inbox_.empty(); });
  batches.swap(inbox_);
  inbox_bytes_ = 0;
  return batches;
}

bool ReplicaInbox::pause(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return !wake_.wait_for(lock, timeout, [&] { return stopping_; });
}

void ReplicaInbox::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
}

bool ReplicaInbox::stopping() {
  std::lock_guard lock(mutex_);
  return stopping_;
}

bool ReplicaInbox::take_rejoined() {
  std::lock_guard lock(mutex_);
  return std::exchange(rejoined_, false);
}

std::size_t ReplicaInbox::dropped() {
  std::lock_guard lock(mutex_);
  return dropped_;
}

}  // namespace ispars::client
