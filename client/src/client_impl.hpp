#pragma once
// The client's DDS side (private to client/src): its participant, request writers (queries and
// changes), reply, status, announcement and tour-progress readers, and the call with retries.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fmt/format.h>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "ispars/client/client.hpp"
#include "ispars/wire/convert.hpp"
#include "ispars/wire/daemon_trust.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/latest_samples.hpp"
#include "ispars/wire/topics.hpp"
#include "ispars/wire/safe_type.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::client {
namespace fdds = eprosima::fastdds::dds;

// Tour progress addressed to this client, handed to the current callback.
class TourProgressListener final : public fdds::DataReaderListener {
 public:
  void on_data_available(fdds::DataReader* reader) override {
    msg::TourProgress p;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&p, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data || p.client_id() != client_id) continue;
      std::lock_guard lock(mutex);
      if (callback) callback(p.seconds(), p.cost(), p.lower_bound());
    }
  }
  std::string client_id;
  std::mutex mutex;
  std::function<void(double, double, double)> callback;
};

class Client::Impl final : public fdds::DataReaderListener {
 public:
  explicit Impl(const ClientOptions& options)
      : options_(options),
        participant_(options.participant),
        query_type_(new wire::SafeType<msg::QueryRequestPubSubType>()),
        change_type_(new wire::SafeType<msg::ChangeRequestPubSubType>()),
        reply_type_(new wire::SafeType<msg::ReplyPubSubType>()),
        status_type_(new wire::SafeType<msg::SceneStatusPubSubType>()),
        daemon_type_(new wire::SafeType<msg::DaemonInfoPubSubType>()),
        // A scene's status counts only when written by the participant that announces the daemon
        // it names (transport identity): a status from anyone else is held, never shown.
        statuses_([](const msg::SceneStatus& s) { return s.scene().to_string(); },
                  [this](const msg::SceneStatus&) { status_changed_.notify_all(); },
                  wire::statuses_from_their_daemon(daemons_)),
        daemons_([](const msg::DaemonInfo& d) { return d.server_id().to_string(); },
                 [this](const msg::DaemonInfo&) { statuses_.recheck(); }) {
    fdds::DomainParticipant* p = participant_.get();
    fdds::Topic* query_topic = wire::find_or_create_topic(p, query_type_, wire::kQueryTopic);
    fdds::Topic* change_topic = wire::find_or_create_topic(p, change_type_, wire::kChangeTopic);
    fdds::Topic* reply_topic = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
    fdds::Topic* status_topic = wire::find_or_create_topic(p, status_type_, wire::kStatusTopic);
    fdds::Topic* daemon_topic = wire::find_or_create_topic(p, daemon_type_, wire::kDaemonsTopic);
    id_ = wire::identity_of(participant_->guid().guidPrefix);
    publisher_ = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    // Replies and tour progress arrive in this client's own partition: no other client's reader
    // matches the daemon's writer for it, and this one matches no one else's.
    reply_subscriber_ = p->create_subscriber(wire::reply_subscriber_qos(id_));
    if (!publisher_ || !subscriber_ || !reply_subscriber_) {
      throw std::runtime_error("cannot create the DDS publisher and subscribers");
    }
    reply_reader_ = reply_subscriber_->create_datareader(reply_topic, wire::request_reply_reader_qos(), this,
                                                         fdds::StatusMask::data_available());
    queries_ = publisher_->create_datawriter(query_topic, wire::request_reply_writer_qos());
    change_topic_ = change_topic;  // its writer is made on the first change request
    status_reader_ = subscriber_->create_datareader(status_topic, wire::state_reader_qos(), &statuses_);
    daemon_reader_ = subscriber_->create_datareader(daemon_topic, wire::state_reader_qos(), &daemons_);
    if (!reply_reader_ || !queries_ || !status_reader_ || !daemon_reader_) {
      throw std::runtime_error("cannot create the client's DDS readers and writers");
    }
    std::random_device rd;
    next_seq_ = (static_cast<std::uint64_t>(rd()) << 20) + 1;  // distinct across restarts with one GUID
  }

  ~Impl() override {
    if (progress_reader_) progress_reader_->set_listener(nullptr);
    reply_reader_->set_listener(nullptr);
    status_reader_->set_listener(nullptr);
    daemon_reader_->set_listener(nullptr);
    // Delete the readers now, while the listeners they point to still exist.
    participant_->delete_contained_entities();
  }

  void on_data_available(fdds::DataReader* reader) override {
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data || reply.client_id() != id_) continue;  // another client's reply
      {
        std::lock_guard lock(mutex_);
        if (waiting_.count(reply.request_seq()) == 0) continue;  // late duplicate of an answered request
        replies_[reply.request_seq()] = reply;
      }
      reply_arrived_.notify_all();
    }
  }

  std::vector<msg::DaemonInfo> daemons(std::chrono::milliseconds timeout) {
    daemons_.wait_for(timeout, [](const auto& latest) { return !latest.empty(); });
    return daemons_.all();
  }

  std::string no_daemon_message() const {
    return fmt::format("no isparsd answered on DDS domain {} within {:.1f} s (is it running, on this domain{}?)",
                       options_.participant.domain, options_.timeout.count() / 1000.0,
                       options_.participant.profile_file.empty() ? ", localhost" : ", with a matching profile");
  }

  fdds::DataWriter* writer_for(const msg::QueryRequest&) const { return queries_; }
  // The change writer, made on first use: under DDS Security a viewer's permissions refuse it,
  // and such a client still queries and follows updates. Null when refused.
  fdds::DataWriter* writer_for(const msg::ChangeRequest&) {
    std::lock_guard lock(mutex_);
    if (changes_ == nullptr && !changes_refused_) {
      changes_ = publisher_->create_datawriter(change_topic_, wire::request_reply_writer_qos());
      changes_refused_ = changes_ == nullptr;
    }
    return changes_;
  }

  template <class Request>
  msg::Reply call(Request request, const std::string& server, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    // The daemon must be discovered (its announcement arrived) before the first send.
    if (!daemons_.wait_for(options_.timeout, [&](const auto& latest) { return latest.count(server) > 0; })) {
      throw ClientError(ClientError::Kind::no_daemon,
                        daemons_.all().empty() ? no_daemon_message()
                                               : fmt::format("daemon {} is not on DDS domain {}", server,
                                                             options_.participant.domain));
    }
    if (const auto info = daemons_.get(server); info && info->protocol() != msg::PROTOCOL_VERSION) {
      throw ClientError(ClientError::Kind::protocol,
                        fmt::format("daemon {} speaks ispars protocol {}; this client speaks {} (use a client of "
                                    "the daemon's release)",
                                    server, info->protocol(), msg::PROTOCOL_VERSION));
    }
    fdds::DataWriter* writer = writer_for(request);
    if (writer == nullptr) {
      throw ClientError(ClientError::Kind::forbidden,
                        fmt::format("this client's DDS Security permissions do not allow {} (topic {}): use an "
                                    "operator identity",
                                    wire::to_string(request.args()._d()), wire::kChangeTopic));
    }
    request.client_id(id_);
    request.server_id(server);
    request.protocol(msg::PROTOCOL_VERSION);
    std::unique_lock lock(mutex_);
    request.request_seq(next_seq_++);
    const std::uint64_t seq = request.request_seq();
    waiting_.insert(seq);
    while (std::chrono::steady_clock::now() < deadline) {
      lock.unlock();
      // Our request writer matched a request reader before sending (DDS-RPC 1.0 sec. 7.6.2). The
      // daemon makes its writer for our partition on our first request and holds the reply until
      // our reply reader has matched it.
      wait_matched(writer, deadline);
      Request copy = request;
      writer->write(&copy);
      lock.lock();
      const auto retry_at = std::min(deadline, std::chrono::steady_clock::now() + options_.retry_interval);
      if (reply_arrived_.wait_until(lock, retry_at, [&] { return replies_.count(seq) > 0; })) {
        msg::Reply reply = std::move(replies_[seq]);
        replies_.erase(seq);
        waiting_.erase(seq);
        return reply;
      }
      if (!daemons_.get(server)) {
        waiting_.erase(seq);
        throw ClientError(ClientError::Kind::no_daemon,
                          fmt::format("daemon {} left DDS domain {} before answering {}", server,
                                      options_.participant.domain, wire::to_string(request.args()._d())));
      }
    }
    waiting_.erase(seq);
    throw ClientError(ClientError::Kind::timeout,
                      fmt::format("daemon {} did not answer {} on DDS domain {} within {:.1f} s", server,
                                  wire::to_string(request.args()._d()), options_.participant.domain,
                                  timeout.count() / 1000.0));
  }

  void wait_matched(fdds::DataWriter* writer, std::chrono::steady_clock::time_point deadline) {
    for (;;) {
      fdds::PublicationMatchedStatus pub;
      writer->get_publication_matched_status(pub);
      if (pub.current_count > 0 || std::chrono::steady_clock::now() >= deadline) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  ClientOptions options_;
  wire::Participant participant_;
  fdds::TypeSupport query_type_, change_type_, reply_type_, status_type_, daemon_type_;
  fdds::Publisher* publisher_ = nullptr;
  fdds::Subscriber* subscriber_ = nullptr;
  fdds::Subscriber* reply_subscriber_ = nullptr;  // in this client's reply partition
  fdds::DataReader* reply_reader_ = nullptr;
  fdds::DataWriter* queries_ = nullptr;
  fdds::Topic* change_topic_ = nullptr;
  fdds::DataWriter* changes_ = nullptr;
  bool changes_refused_ = false;
  fdds::DataReader* status_reader_ = nullptr;
  fdds::DataReader* daemon_reader_ = nullptr;
  std::condition_variable status_changed_;
  wire::LatestSamples<msg::SceneStatus> statuses_;
  wire::LatestSamples<msg::DaemonInfo> daemons_;
  std::string id_;

  fdds::TypeSupport progress_type_{new wire::SafeType<msg::TourProgressPubSubType>()};
  fdds::DataReader* progress_reader_ = nullptr;
  TourProgressListener progress_;

  // Subscribes to tour progress on first use.
  void ensure_progress_reader() {
    std::lock_guard lock(mutex_);
    if (progress_reader_) return;
    progress_.client_id = id_;
    fdds::Topic* topic = wire::find_or_create_topic(participant_.get(), progress_type_, wire::kTourProgressTopic);
    progress_reader_ = reply_subscriber_->create_datareader(topic, wire::request_reply_reader_qos(), &progress_,
                                                      fdds::StatusMask::data_available());
  }

  std::mutex mutex_;
  std::condition_variable reply_arrived_;
  std::uint64_t next_seq_ = 1;
  std::set<std::uint64_t> waiting_;
  std::map<std::uint64_t, msg::Reply> replies_;
};

}  // namespace ispars::client
