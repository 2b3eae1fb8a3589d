#include "support/raw_peer.hpp"

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
#include "ispars/wire/topics.hpp"
#include "ispars/wire/safe_type.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::test {
namespace fdds = eprosima::fastdds::dds;

class RawPeer::Impl final : public fdds::DataReaderListener {
 public:
  explicit Impl(int domain) : participant_({domain, "", "ispars", "raw peer"}) {
    fdds::DomainParticipant* p = participant_.get();
    auto* query = wire::find_or_create_topic(p, query_type_, wire::kQueryTopic);
    auto* reply = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
    auto* daemons = wire::find_or_create_topic(p, daemon_type_, wire::kDaemonsTopic);
    auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (!pub || !sub) throw std::runtime_error("raw peer: no publisher or subscriber");
    replies_ = sub->create_datareader(reply, wire::request_reply_reader_qos(), this, fdds::StatusMask::data_available());
    queries_ = pub->create_datawriter(query, wire::request_reply_writer_qos());
    announcements_ = pub->create_datawriter(daemons, wire::state_writer_qos());
    if (!replies_ || !queries_ || !announcements_) throw std::runtime_error("raw peer: endpoints not created");
    id_ = wire::identity_of(participant_->guid().guidPrefix);
  }
  ~Impl() override {
    replies_->set_listener(nullptr);
    participant_->delete_contained_entities();
  }

  void on_data_available(fdds::DataReader* reader) override {
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data || reply.client_id() != id_) continue;
      std::lock_guard lock(mutex_);
      replies_by_seq_[reply.request_seq()] = reply;
      arrived_.notify_all();
    }
  }

  wire::Participant participant_;
  fdds::TypeSupport query_type_{new wire::SafeType<msg::QueryRequestPubSubType>()};
  fdds::TypeSupport reply_type_{new wire::SafeType<msg::ReplyPubSubType>()};
  fdds::TypeSupport daemon_type_{new wire::SafeType<msg::DaemonInfoPubSubType>()};
  fdds::DataReader* replies_ = nullptr;
  fdds::DataWriter* queries_ = nullptr;
  fdds::DataWriter* announcements_ = nullptr;
  std::string id_;
  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  std::map<std::uint64_t, msg::Reply> replies_by_seq_;
};

RawPeer::RawPeer(int domain) : impl_(std::make_unique<Impl>(domain)) {}
RawPeer::~RawPeer() = default;

namespace {

// Waits until the query writer and the reply reader have both matched a daemon.
bool wait_matched(fdds::DataWriter* writer, fdds::DataReader* reader, std::chrono::steady_clock::time_point deadline) {
  for (;;) {
    fdds::PublicationMatchedStatus pub;
    fdds::SubscriptionMatchedStatus sub;
    writer->get_publication_matched_status(pub);
    reader->get_subscription_matched_status(sub);
    if (pub.current_count > 0 && sub.current_count > 0) return true;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace

bool RawPeer::post(msg::QueryRequest request, std::chrono::milliseconds timeout) {
  if (!wait_matched(impl_->queries_, impl_->replies_, std::chrono::steady_clock::now() + timeout)) return false;
  return impl_->queries_->write(&request);
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
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  if (!wait_matched(impl_->queries_, impl_->replies_, deadline)) return std::nullopt;
  request.client_id(impl_->id_);
  const std::uint64_t seq = request.request_seq();
  // Resent every second until answered (the daemon de-duplicates), as a client does.
  std::unique_lock lock(impl_->mutex_);
  while (std::chrono::steady_clock::now() < deadline) {
    lock.unlock();
    impl_->queries_->write(&request);
    lock.lock();
    const auto retry = std::min(deadline, std::chrono::steady_clock::now() + std::chrono::seconds(1));
    if (impl_->arrived_.wait_until(lock, retry, [&] { return impl_->replies_by_seq_.count(seq) > 0; })) {
      return impl_->replies_by_seq_[seq];
    }
  }
  return std::nullopt;
}

void RawPeer::announce(const msg::DaemonInfo& info) {
  msg::DaemonInfo copy = info;
  impl_->announcements_->write(&copy);
}

}  // namespace ispars::test
