#pragma once
// The client's DDS side (private to client/src): its link (participant, request writers, reply,
// status, announcement and tour-progress readers: client_link.hpp), the listeners that outlive
// it, the call with retries, and the rejoin under DDS Security (client_rejoin.cpp).

#include <fmt/format.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <algorithm>
#include <condition_variable>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <shared_mutex>
#include <sstream>
#include <thread>
#include <type_traits>

#include "client_link.hpp"
#include "ispars/client/client.hpp"
#include "ispars/wire/convert.hpp"
#include "ispars/wire/daemon_trust.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/latest_samples.hpp"
#include "ispars/wire/rejoin_schedule.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/topics.hpp"
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
      if (!info.valid_data) continue;
      std::lock_guard lock(mutex);
      if (p.client_id() != client_id) continue;
      if (callback) callback(p.seconds(), p.cost(), p.lower_bound());
    }
  }
  std::mutex mutex;
  std::string client_id;  // under mutex: the current link's
  std::function<void(double, double, double)> callback;
};

class Client::Impl final : public fdds::DataReaderListener {
 public:
  explicit Impl(const ClientOptions& options)
      : options_(options),
        // A scene's status counts only when written by the participant that announces the daemon
        // it names (transport identity): a status from anyone else is held, never shown.
        statuses_([](const msg::SceneStatus& s) { return s.scene().to_string(); },
                  [this](const msg::SceneStatus&) { status_changed_.notify_all(); },
                  wire::statuses_from_their_daemon(daemons_)),
        daemons_([](const msg::DaemonInfo& d) { return d.server_id().to_string(); },
                 [this](const msg::DaemonInfo&) { statuses_.recheck(); }) {
    // Made here, once every member exists: its readers call this object from the moment they
    // are created (the daemon's route-open reply can arrive before the link's constructor returns).
    auto link = std::make_unique<ClientLink>(options.participant, listeners());
    {
      std::unique_lock lock(link_mutex_);
      link_ = std::move(link);
    }
    set_id(link_->id());
    std::random_device rd;
    next_seq_ = (static_cast<std::uint64_t>(rd()) << 20) + 1;  // distinct across restarts with one GUID
    start_rejoin_watch();
  }

  ~Impl() override {
    stop_rejoin_watch();
    std::unique_lock lock(link_mutex_);
    for (ParticipantUser* user : users_) user->detach(link_->participant());
    link_.reset();  // deletes the readers while the listeners they point to still exist
  }

  ClientListeners listeners() { return {this, &statuses_, &daemons_, &progress_}; }

  void on_data_available(fdds::DataReader* reader) override {
    msg::Reply reply;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      {
        std::lock_guard lock(mutex_);
        if (reply.client_id() != id_) continue;                  // another client's reply, or one to a link left behind
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

  std::string id() const {
    std::lock_guard lock(mutex_);
    return id_;
  }

  std::uint64_t rejoins() const {
    std::shared_lock link(link_mutex_);
    return epoch_of_link_;
  }

  template <class Request>
  msg::Reply call(Request request, const std::string& server, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    // The daemon must be discovered (its announcement arrived) before the first send.
    if (!daemons_.wait_for(options_.timeout, [&](const auto& latest) { return latest.count(server) > 0; })) {
      throw ClientError(ClientError::Kind::no_daemon,
                        daemons_.all().empty()
                            ? no_daemon_message()
                            : fmt::format("daemon {} is not on DDS domain {}", server, options_.participant.domain));
    }
    if (const auto info = daemons_.get(server); info && info->protocol() != msg::PROTOCOL_VERSION) {
      throw ClientError(ClientError::Kind::protocol,
                        fmt::format("daemon {} speaks ispars protocol {}; this client speaks {} (use a client of "
                                    "the daemon's release)",
                                    server, info->protocol(), msg::PROTOCOL_VERSION));
    }
    request.server_id(server);
    request.protocol(msg::PROTOCOL_VERSION);
    std::optional<std::uint64_t> sent_on;  // the link the request was first sent from
    std::unique_lock lock(mutex_);
    request.request_seq(next_seq_++);
    const std::uint64_t seq = request.request_seq();
    waiting_.insert(seq);
    lock.unlock();
    struct Forget {  // however the call ends
      Impl& impl;
      std::uint64_t seq;
      ~Forget() {
        std::lock_guard lock(impl.mutex_);
        impl.waiting_.erase(seq);
        impl.replies_.erase(seq);
      }
    } forget{*this, seq};
    while (std::chrono::steady_clock::now() < deadline) {
      send(request, sent_on, deadline);
      lock.lock();
      const auto retry_at = std::min(deadline, std::chrono::steady_clock::now() + options_.retry_interval);
      if (reply_arrived_.wait_until(lock, retry_at, [&] { return replies_.count(seq) > 0; })) {
        msg::Reply reply = std::move(replies_[seq]);
        lock.unlock();  // `forget` takes the mutex
        return reply;
      }
      lock.unlock();
      if (!daemons_.get(server)) {
        throw ClientError(ClientError::Kind::no_daemon,
                          fmt::format("daemon {} left DDS domain {} before answering {}", server,
                                      options_.participant.domain, wire::to_string(request.args()._d())));
      }
    }
    throw ClientError(
        ClientError::Kind::timeout,
        fmt::format("daemon {} did not answer {} on DDS domain {} within {:.1f} s", server,
                    wire::to_string(request.args()._d()), options_.participant.domain, timeout.count() / 1000.0));
  }

  // Writes `request` as this client's current link: once its writer has matched a request
  // reader (DDS-RPC 1.0 sec. 7.6.2), or at the deadline. The daemon makes its writer for our
  // partition on our first request and holds the reply until our reply reader has matched it.
  // A change first sent before a rejoin is not sent again from the new link: the daemon would
  // take it for another client's and do it again.
  template <class Request>
  void send(Request& request, std::optional<std::uint64_t>& sent_on, std::chrono::steady_clock::time_point deadline) {
    for (;;) {
      {
        std::shared_lock link(link_mutex_);
        if constexpr (std::is_same_v<Request, msg::ChangeRequest>) {
          if (sent_on && *sent_on != epoch_of_link_) {
            throw ClientError(ClientError::Kind::timeout,
                              fmt::format("this client rejoined DDS domain {} while waiting for the answer to {}; "
                                          "the daemon may have done it: check `ispars stats {}` before sending it "
                                          "again",
                                          options_.participant.domain, wire::to_string(request.args()._d()),
                                          request.scene().to_string()));
          }
        }
        fdds::DataWriter* writer = writer_for(request);
        if (writer == nullptr) {
          throw ClientError(ClientError::Kind::forbidden,
                            fmt::format("this client's DDS Security permissions do not allow {} (topic {}): use an "
                                        "operator identity",
                                        wire::to_string(request.args()._d()), wire::kChangeTopic));
        }
        fdds::PublicationMatchedStatus matched;
        writer->get_publication_matched_status(matched);
        if (matched.current_count > 0 || std::chrono::steady_clock::now() >= deadline) {
          request.client_id(link_->id());
          Request copy = request;
          writer->write(&copy);
          sent_on = epoch_of_link_;
          return;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  // Under link_mutex_.
  fdds::DataWriter* writer_for(const msg::QueryRequest&) const { return link_->queries(); }
  fdds::DataWriter* writer_for(const msg::ChangeRequest&) const { return link_->changes(); }

  // Subscribes to tour progress on first use (and on every link after).
  void ensure_progress_reader() {
    std::shared_lock link(link_mutex_);
    link_->ensure_progress_reader();
  }

  void add_user(ParticipantUser& user) {
    std::unique_lock link(link_mutex_);
    user.attach(link_->participant());
    users_.push_back(&user);
  }
  void remove_user(ParticipantUser& user) {
    std::unique_lock link(link_mutex_);
    std::erase(users_, &user);
    user.detach(link_->participant());
  }

  // client_rejoin.cpp
  void start_rejoin_watch();
  void stop_rejoin_watch();
  void watch_for_returned_peers(std::stop_token stop);
  bool rejoin(const std::string& why);

  void set_id(const std::string& id) {
    {
      std::lock_guard lock(mutex_);
      id_ = id;
    }
    std::lock_guard lock(progress_.mutex);
    progress_.client_id = id;
  }

  ClientOptions options_;
  std::condition_variable status_changed_;
  wire::LatestSamples<msg::SceneStatus> statuses_;
  wire::LatestSamples<msg::DaemonInfo> daemons_;
  TourProgressListener progress_;

  // The link, replaced whole by a rejoin: its users (replicas) move with it.
  mutable std::shared_mutex link_mutex_;
  std::unique_ptr<ClientLink> link_;
  std::uint64_t epoch_of_link_ = 0;  // under link_mutex_: rejoins so far
  std::vector<ParticipantUser*> users_;

  mutable std::mutex mutex_;  // the calls' state
  std::condition_variable reply_arrived_;
  std::string id_;  // the current link's identity
  std::uint64_t next_seq_ = 1;
  std::set<std::uint64_t> waiting_;
  std::map<std::uint64_t, msg::Reply> replies_;

  // The rejoin watch (secured clients only).
  std::mutex watch_mutex_;
  std::condition_variable_any watch_wake_;
  std::jthread watch_;
  wire::RejoinSchedule rejoin_schedule_{std::chrono::seconds(30), std::chrono::seconds(10)};  // the watch's
};

}  // namespace ispars::client
