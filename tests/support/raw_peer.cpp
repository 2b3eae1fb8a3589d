#include "support/raw_peer.hpp"

#include <algorithm>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <condition_variable>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "ispars/wire/identity.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"
#include "support/eventually.hpp"

namespace ispars::test {
namespace fdds = eprosima::fastdds::dds;

class RawPeer::Impl final : public fdds::DataReaderListener {
 public:
  Impl(int domain, const std::string& security, bool read_replies)
      : participant_({domain, "", "ispars", "raw peer", security}) {
    fdds::DomainParticipant* p = participant_.get();
    auto* query = wire::find_or_create_topic(p, query_type_, wire::kQueryTopic);
    reply_topic_ = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
    id_ = wire::identity_of(participant_->guid().guidPrefix);
    auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    reply_subscriber_ = p->create_subscriber(wire::reply_subscriber_qos(id_));
    if (!pub || !reply_subscriber_) throw std::runtime_error("raw peer: no publisher or subscriber");
    queries_ = pub->create_datawriter(query, wire::request_reply_writer_qos());
    publisher_ = pub;
    if (!queries_) throw std::runtime_error("raw peer: query writer not created");
    if (read_replies) open_reply_reader();
  }
  ~Impl() override {
    if (replies_ != nullptr) replies_->set_listener(nullptr);
    participant_->delete_contained_entities();
  }

  template <class Request>
  std::optional<msg::Reply> send(fdds::DataWriter* writer, Request& request, std::chrono::milliseconds timeout);

  // The change writer, made on first use (a viewer's permissions do not allow one).
  fdds::DataWriter* change_writer() {
    if (changes_ == nullptr) {
      auto* topic = wire::find_or_create_topic(participant_.get(), change_type_, wire::kChangeTopic);
      changes_ = publisher_->create_datawriter(topic, wire::request_reply_writer_qos());
      if (changes_ == nullptr) throw std::runtime_error("raw peer: change writer not created");
    }
    return changes_;
  }

  void open_reply_reader() {
    if (replies_ != nullptr) return;
    replies_ = reply_subscriber_->create_datareader(reply_topic_, wire::request_reply_reader_qos(), this,
                                                    fdds::StatusMask::data_available());
    if (replies_ == nullptr) throw std::runtime_error("raw peer: reply reader not created");
  }

  void on_data_available(fdds::DataReader* reader) override {
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      std::lock_guard lock(mutex_);
      if (reply.client_id() != id_) {
        ++foreign_;
        continue;
      }
      if (reply.request_seq() == 0) {  // the daemon's route-open reply: no request has 0
        ++route_opens_;
        continue;
      }
      replies_by_seq_[reply.request_seq()] = reply;
      ++deliveries_[reply.request_seq()];
      arrived_.notify_all();
    }
  }

  wire::Participant participant_;
  fdds::TypeSupport query_type_{new wire::SafeType<msg::QueryRequestPubSubType>()};
  fdds::TypeSupport change_type_{new wire::SafeType<msg::ChangeRequestPubSubType>()};
  fdds::TypeSupport reply_type_{new wire::SafeType<msg::ReplyPubSubType>()};
  fdds::TypeSupport daemon_type_{new wire::SafeType<msg::DaemonInfoPubSubType>()};
  fdds::TypeSupport update_type_{new wire::SafeType<msg::UpdateBatchPubSubType>()};
  fdds::Topic* reply_topic_ = nullptr;
  fdds::Subscriber* reply_subscriber_ = nullptr;
  fdds::DataReader* replies_ = nullptr;
  fdds::DataWriter* queries_ = nullptr;
  fdds::DataWriter* changes_ = nullptr;
  fdds::Publisher* publisher_ = nullptr;
  fdds::DataWriter* announcements_ = nullptr;  // made by the first announce()
  std::string id_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::uint64_t, msg::Reply> replies_by_seq_;
  std::map<std::uint64_t, std::size_t> deliveries_;  // replies received, by sequence number
  std::size_t foreign_ = 0;
  std::size_t route_opens_ = 0;
};

RawPeer::RawPeer(int domain, const std::string& security, bool read_replies)
    : impl_(std::make_unique<Impl>(domain, security, read_replies)) {}

void RawPeer::open_reply_reader() { impl_->open_reply_reader(); }

std::size_t RawPeer::route_opens() const {
  std::lock_guard lock(impl_->mutex_);
  return impl_->route_opens_;
}

std::size_t RawPeer::foreign_replies() const {
  std::lock_guard lock(impl_->mutex_);
  return impl_->foreign_;
}
RawPeer::~RawPeer() = default;

namespace {

// Waits until the query writer has matched a daemon (its writer for this peer's reply partition
// is made on the first request).
bool wait_matched(fdds::DataWriter* writer, std::chrono::steady_clock::time_point deadline) {
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  return eventually(
      [&] {
        fdds::PublicationMatchedStatus pub;
        writer->get_publication_matched_status(pub);
        return pub.current_count > 0;
      },
      std::max(left, std::chrono::milliseconds(0)), "the query writer matches a daemon", std::chrono::milliseconds(10));
}

}  // namespace

bool RawPeer::post(msg::QueryRequest request, std::chrono::milliseconds timeout) {
  if (!wait_matched(impl_->queries_, std::chrono::steady_clock::now() + timeout)) return false;
  return impl_->queries_->write(&request);
}

bool RawPeer::post(msg::ChangeRequest request, std::chrono::milliseconds timeout) {
  fdds::DataWriter* writer = impl_->change_writer();
  if (!wait_matched(writer, std::chrono::steady_clock::now() + timeout)) return false;
  return writer->write(&request);
}

const std::string& RawPeer::identity() const { return impl_->id_; }

std::size_t RawPeer::replies_received() const {
  std::lock_guard lock(impl_->mutex_);
  return impl_->replies_by_seq_.size();
}

std::vector<msg::Reply> RawPeer::replies() const {
  std::lock_guard lock(impl_->mutex_);
  std::vector<msg::Reply> out;
  for (const auto& [seq, reply] : impl_->replies_by_seq_) out.push_back(reply);
  return out;
}

std::optional<msg::Reply> RawPeer::send(msg::QueryRequest request, std::chrono::milliseconds timeout) {
  return impl_->send(impl_->queries_, request, timeout);
}

std::optional<msg::Reply> RawPeer::send(msg::ChangeRequest request, std::chrono::milliseconds timeout) {
  return impl_->send(impl_->change_writer(), request, timeout);
}

template <class Request>
std::optional<msg::Reply> RawPeer::Impl::send(fdds::DataWriter* writer, Request& request,
                                              std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  if (!wait_matched(writer, deadline)) return std::nullopt;
  request.client_id(id_);
  const std::uint64_t seq = request.request_seq();
  // Resent every second until answered (the daemon de-duplicates), as a client does.
  std::unique_lock lock(mutex_);
  while (std::chrono::steady_clock::now() < deadline) {
    lock.unlock();
    writer->write(&request);
    lock.lock();
    const auto retry = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1));
    if (arrived_.wait_until(lock, retry, [&] { return replies_by_seq_.count(seq) > 0; })) return replies_by_seq_[seq];
  }
  return std::nullopt;
}

std::size_t RawPeer::replies_to(std::uint64_t seq) const {
  std::lock_guard lock(impl_->mutex_);
  const auto it = impl_->deliveries_.find(seq);
  return it == impl_->deliveries_.end() ? 0 : it->second;
}

std::optional<msg::Reply> RawPeer::reply_to(std::uint64_t seq) const {
  std::lock_guard lock(impl_->mutex_);
  const auto it = impl_->replies_by_seq_.find(seq);
  if (it == impl_->replies_by_seq_.end()) return std::nullopt;
  return it->second;
}

std::size_t RawPeer::kept_update_batches(const std::string& scene, std::chrono::milliseconds wait) {
  fdds::DomainParticipant* p = impl_->participant_.get();
  auto* topic = wire::find_or_create_topic(p, impl_->update_type_, wire::kUpdatesTopic);
  auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
  auto* reader = sub ? sub->create_datareader(topic, wire::updates_reader_qos()) : nullptr;
  if (reader == nullptr) throw std::runtime_error("raw peer: update reader not created");
  std::this_thread::sleep_for(wait);
  std::size_t count = 0;
  msg::UpdateBatch batch;
  fdds::SampleInfo info;
  while (reader->take_next_sample(&batch, &info) == ReturnCode_t::RETCODE_OK) {
    if (info.valid_data && batch.scene() == scene) ++count;
  }
  sub->delete_datareader(reader);
  p->delete_subscriber(sub);
  return count;
}

void RawPeer::announce(const msg::DaemonInfo& info) {
  if (impl_->announcements_ == nullptr) {
    auto* daemons = wire::find_or_create_topic(impl_->participant_.get(), impl_->daemon_type_, wire::kDaemonsTopic);
    impl_->announcements_ = impl_->publisher_->create_datawriter(daemons, wire::state_writer_qos());
    if (impl_->announcements_ == nullptr) throw std::runtime_error("raw peer: announcement writer not created");
  }
  msg::DaemonInfo copy = info;
  impl_->announcements_->write(&copy);
}

}  // namespace ispars::test
