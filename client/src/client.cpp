#include "ispars/client/client.hpp"

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
#include <mutex>
#include <random>
#include <sstream>

#include "ispars/roadmap_log.hpp"
#include "ispars/wire/convert.hpp"
#include "ispars/wire/latest_samples.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::client {
namespace fdds = eprosima::fastdds::dds;

namespace {

bool busy_state(msg::SceneState s) {
  return s == msg::SCENE_QUEUED || s == msg::SCENE_BUILDING || s == msg::SCENE_REPLAYING;
}

}  // namespace

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
        request_type_(new msg::RequestPubSubType()),
        reply_type_(new msg::ReplyPubSubType()),
        status_type_(new msg::SceneStatusPubSubType()),
        daemon_type_(new msg::DaemonInfoPubSubType()),
        statuses_([](const msg::SceneStatus& s) { return s.scene(); },
                  [this](const msg::SceneStatus&) { status_changed_.notify_all(); }),
        daemons_([](const msg::DaemonInfo& d) { return d.server_id(); }) {
    fdds::DomainParticipant* p = participant_.get();
    fdds::Topic* request_topic = wire::find_or_create_topic(p, request_type_, wire::kRequestTopic);
    fdds::Topic* reply_topic = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
    fdds::Topic* status_topic = wire::find_or_create_topic(p, status_type_, wire::kStatusTopic);
    fdds::Topic* daemon_topic = wire::find_or_create_topic(p, daemon_type_, wire::kDaemonsTopic);
    publisher_ = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    subscriber_ = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (!publisher_ || !subscriber_) throw std::runtime_error("cannot create the DDS publisher and subscriber");
    // The reply reader first: its GUID is this client's id.
    reply_reader_ = subscriber_->create_datareader(reply_topic, wire::request_reply_reader_qos(), this,
                                                   fdds::StatusMask::data_available());
    requests_ = publisher_->create_datawriter(request_topic, wire::request_reply_writer_qos());
    status_reader_ = subscriber_->create_datareader(status_topic, wire::state_reader_qos(), &statuses_);
    daemon_reader_ = subscriber_->create_datareader(daemon_topic, wire::state_reader_qos(), &daemons_);
    if (!reply_reader_ || !requests_ || !status_reader_ || !daemon_reader_) {
      throw std::runtime_error("cannot create the client's DDS readers and writers");
    }
    std::ostringstream guid;
    guid << reply_reader_->guid();
    id_ = guid.str();
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

  msg::Reply call(msg::Request request, const std::string& server) { return call(std::move(request), server, options_.timeout); }

  msg::Reply call(msg::Request request, const std::string& server, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    // The daemon must be discovered (its announcement arrived) before the first send.
    if (!daemons_.wait_for(options_.timeout, [&](const auto& latest) { return latest.count(server) > 0; })) {
      throw ClientError(ClientError::Kind::no_daemon,
                        daemons_.all().empty() ? no_daemon_message()
                                               : fmt::format("daemon {} is not on DDS domain {}", server,
                                                             options_.participant.domain));
    }
    request.client_id(id_);
    request.server_id(server);
    std::unique_lock lock(mutex_);
    request.request_seq(next_seq_++);
    const std::uint64_t seq = request.request_seq();
    waiting_.insert(seq);
    while (std::chrono::steady_clock::now() < deadline) {
      lock.unlock();
      // Both directions matched before sending (DDS-RPC 1.0 sec. 7.6.2): our reply reader with a
      // reply writer, our request writer with a request reader.
      wait_matched(deadline);
      msg::Request copy = request;
      requests_->write(&copy);
      lock.lock();
      const auto retry_at = std::min(deadline, std::chrono::steady_clock::now() + options_.retry_interval);
      if (reply_arrived_.wait_until(lock, retry_at, [&] { return replies_.count(seq) > 0; })) {
        msg::Reply reply = std::move(replies_[seq]);
        replies_.erase(seq);
        waiting_.erase(seq);
        return reply;
      }
      if (!daemons_.get(server)) break;  // the daemon went away
    }
    waiting_.erase(seq);
    throw ClientError(ClientError::Kind::timeout,
                      fmt::format("daemon {} did not answer {} on DDS domain {} within {:.1f} s", server,
                                  wire::to_string(request.kind()), options_.participant.domain,
                                  timeout.count() / 1000.0));
  }

  void wait_matched(std::chrono::steady_clock::time_point deadline) {
    for (;;) {
      fdds::PublicationMatchedStatus pub;
      fdds::SubscriptionMatchedStatus sub;
      requests_->get_publication_matched_status(pub);
      reply_reader_->get_subscription_matched_status(sub);
      if ((pub.current_count > 0 && sub.current_count > 0) || std::chrono::steady_clock::now() >= deadline) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

  ClientOptions options_;
  wire::Participant participant_;
  fdds::TypeSupport request_type_, reply_type_, status_type_, daemon_type_;
  fdds::Publisher* publisher_ = nullptr;
  fdds::Subscriber* subscriber_ = nullptr;
  fdds::DataReader* reply_reader_ = nullptr;
  fdds::DataWriter* requests_ = nullptr;
  fdds::DataReader* status_reader_ = nullptr;
  fdds::DataReader* daemon_reader_ = nullptr;
  std::condition_variable status_changed_;
  wire::LatestSamples<msg::SceneStatus> statuses_;
  wire::LatestSamples<msg::DaemonInfo> daemons_;
  std::string id_;

  fdds::TypeSupport progress_type_{new msg::TourProgressPubSubType()};
  fdds::DataReader* progress_reader_ = nullptr;
  TourProgressListener progress_;

  // Subscribes to tour progress on first use.
  void ensure_progress_reader() {
    std::lock_guard lock(mutex_);
    if (progress_reader_) return;
    progress_.client_id = id_;
    fdds::Topic* topic = wire::find_or_create_topic(participant_.get(), progress_type_, wire::kTourProgressTopic);
    progress_reader_ = subscriber_->create_datareader(topic, wire::request_reply_reader_qos(), &progress_,
                                                      fdds::StatusMask::data_available());
  }

  std::mutex mutex_;
  std::condition_variable reply_arrived_;
  std::uint64_t next_seq_ = 1;
  std::set<std::uint64_t> waiting_;
  std::map<std::uint64_t, msg::Reply> replies_;
};

Client::Client(ClientOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>(options_)) {}
Client::~Client() = default;

const std::string& Client::id() const { return impl_->id_; }
wire::Participant& Client::participant() { return impl_->participant_; }
std::vector<msg::DaemonInfo> Client::daemons() { return impl_->daemons(options_.timeout); }
std::optional<msg::SceneStatus> Client::latest_status(const std::string& scene) const {
  return impl_->statuses_.get(scene);
}

std::string Client::owner_of(const std::string& scene) {
  const auto pick = [&](const std::vector<msg::DaemonInfo>& all) -> std::string {
    for (const auto& d : all) {
      if (std::find(d.loaded().begin(), d.loaded().end(), scene) != d.loaded().end()) return d.server_id();
    }
    return {};
  };
  std::vector<msg::DaemonInfo> all = daemons();
  if (all.empty()) throw ClientError(ClientError::Kind::no_daemon, impl_->no_daemon_message());
  if (std::string owner = pick(all); !owner.empty()) return owner;
  // A second daemon may be discovered a moment after the first: give announcements a moment.
  impl_->daemons_.wait_for(std::chrono::milliseconds(500), [&](const auto& latest) {
    for (const auto& [id, d] : latest) {
      if (std::find(d.loaded().begin(), d.loaded().end(), scene) != d.loaded().end()) return true;
    }
    return false;
  });
  all = impl_->daemons_.all();
  if (std::string owner = pick(all); !owner.empty()) return owner;
  if (!options_.server.empty()) return options_.server;
  for (const auto& d : all) {  // sorted by id
    if (std::find(d.available().begin(), d.available().end(), scene) != d.available().end()) return d.server_id();
  }
  return all.front().server_id();  // it will say what is wrong with the name
}

msg::Reply Client::call_raw(msg::Request request, const std::string& server) {
  const std::string target = server.empty() ? owner_of(request.scene()) : server;
  return impl_->call(std::move(request), target);
}

msg::Reply Client::call(msg::Request request, const std::string& server) {
  return call(std::move(request), server, options_.timeout);
}

namespace {
msg::Request request_for(msg::RequestKind kind, const std::string& scene) {
  msg::Request r;
  r.kind(kind);
  r.scene(scene);
  return r;
}
}  // namespace

std::vector<msg::SceneEntry> Client::list_scenes() {
  std::vector<msg::SceneEntry> out;
  const auto all = daemons();
  if (all.empty()) throw ClientError(ClientError::Kind::no_daemon, impl_->no_daemon_message());
  for (const auto& d : all) {
    const msg::Reply reply = call(request_for(msg::LIST_SCENES, ""), d.server_id());
    out.insert(out.end(), reply.scenes().begin(), reply.scenes().end());
  }
  return out;
}

msg::Reply Client::load(const std::string& scene) { return call(request_for(msg::LOAD_SCENE, scene)); }
msg::Reply Client::unload(const std::string& scene) { return call(request_for(msg::UNLOAD_SCENE, scene)); }
msg::Reply Client::cancel(const std::string& scene) { return call(request_for(msg::CANCEL, scene)); }
msg::Reply Client::drop(const std::string& scene) { return call(request_for(msg::DROP, scene)); }
msg::Reply Client::verify(const std::string& scene) { return call(request_for(msg::VERIFY, scene)); }
msg::SceneStatus Client::stats(const std::string& scene) { return call(request_for(msg::STATS, scene)).status(); }

msg::Reply Client::build(const std::string& scene, const BuildArgs& args) {
  msg::Request r = request_for(msg::BUILD, scene);
  r.method(args.method);
  r.variant(args.variant);
  r.samples(args.samples);
  r.seed(args.seed);
  r.replace(args.replace);
  for (const auto& [name, value] : args.overrides) {
    msg::Parameter p;
    p.name(name);
    p.value(value);
    r.overrides().push_back(p);
  }
  return call(r);
}

msg::Reply Client::extend(const std::string& scene, std::uint64_t samples) {
  msg::Request r = request_for(msg::EXTEND, scene);
  r.samples(samples);
  return call(r);
}

msg::Reply Client::path(const std::string& scene, const Vec3& from, const Vec3& to) {
  msg::Request r = request_for(msg::PATH, scene);
  r.from(wire::to_message(from));
  r.to(wire::to_message(to));
  return call(r);
}

Snapshot Client::snapshot(const std::string& scene) {
  const std::string server = owner_of(scene);
  for (int attempt = 0; attempt < 3; ++attempt) {
    msg::Request r = request_for(msg::SNAPSHOT, scene);
    msg::Reply first = call(r, server);
    Snapshot s;
    s.scene = scene;
    s.generation = first.snapshot_generation();
    s.version = first.snapshot_version();
    s.status = first.status();
    s.root = wire::from_message(first.root());
    for (const auto& p : first.pois()) s.pois.push_back(wire::from_message(p));
    std::string bytes(first.chunk().begin(), first.chunk().end());
    bool restarted = false;
    for (std::uint32_t i = 1; i < first.chunk_count(); ++i) {
      r.snapshot_generation(s.generation);
      r.snapshot_version(s.version);
      r.chunk_index(i);
      msg::Reply part = call_raw(r, server);
      if (!part.ok()) {  // the roadmap was rebuilt meanwhile: start again
        restarted = true;
        break;
      }
      bytes.append(part.chunk().begin(), part.chunk().end());
    }
    if (restarted) continue;
    try {
      s.roadmap = Roadmap(s.pois.size());
      apply_batch(s.roadmap, decode_batch(bytes));
    } catch (const std::runtime_error& e) {
      throw ClientError(ClientError::Kind::protocol, std::string("snapshot of '") + scene + "' is damaged: " + e.what());
    }
    return s;
  }
  throw ClientError(ClientError::Kind::protocol, "the roadmap of '" + scene + "' kept changing generation during the snapshot");
}

msg::Reply Client::call(msg::Request request, const std::string& server, std::chrono::milliseconds timeout) {
  const std::string target = server.empty() ? owner_of(request.scene()) : server;
  msg::Reply reply = impl_->call(std::move(request), target, timeout);
  if (!reply.ok()) throw ClientError(ClientError::Kind::rejected, reply.error());
  return reply;
}

msg::Reply Client::tour(const std::string& scene, double budget, std::uint64_t seed,
                        const std::vector<std::uint32_t>& targets,
                        const std::function<void(double seconds, double cost, double bound)>& progress) {
  impl_->ensure_progress_reader();
  {
    std::lock_guard lock(impl_->progress_.mutex);
    impl_->progress_.callback = progress;
  }
  msg::Request r = request_for(msg::TOUR, scene);
  r.budget(budget);
  r.seed(seed);
  r.targets(targets);
  // The daemon answers when the search ends: wait for the budget on top of the usual timeout.
  const auto timeout = options_.timeout + std::chrono::milliseconds(static_cast<long>(std::max(0.0, budget) * 1000));
  msg::Reply reply;
  try {
    reply = call(r, {}, timeout);
  } catch (...) {
    std::lock_guard lock(impl_->progress_.mutex);
    impl_->progress_.callback = nullptr;
    throw;
  }
  std::lock_guard lock(impl_->progress_.mutex);
  impl_->progress_.callback = nullptr;
  return reply;
}

msg::SceneStatus Client::wait_idle(const std::string& scene, const std::function<void(const msg::SceneStatus&)>& progress,
                                   std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  msg::SceneStatus last = stats(scene);  // through the owner: fails clearly when not loaded
  if (progress) progress(last);
  std::uint64_t seen_version = last.version();
  std::uint64_t seen_samples = last.samples_done();
  msg::SceneState seen_state = last.state();
  while (busy_state(last.state())) {
    if (std::chrono::steady_clock::now() >= deadline) {
      throw ClientError(ClientError::Kind::timeout, fmt::format("scene '{}' still {} after {:.0f} s", scene,
                                                                wire::to_string(last.state()), timeout.count() / 1000.0));
    }
    impl_->statuses_.wait_for(std::chrono::milliseconds(500), [&](const auto& latest) {
      const auto it = latest.find(scene);
      return it != latest.end() && (it->second.samples_done() != seen_samples || it->second.state() != seen_state ||
                                    it->second.version() != seen_version);
    });
    if (const auto s = impl_->statuses_.get(scene); s && s->status_seq() < last.status_seq() &&
                                                     s->server_id() == last.server_id()) {
      // older than what we know: ignore
    } else if (s) {
      if (s->server_id() != last.server_id() || s->state() == msg::SCENE_UNLOADED) {
        throw ClientError(ClientError::Kind::protocol, fmt::format("scene '{}' was unloaded while waiting", scene));
      }
      last = *s;
    } else if (!impl_->daemons_.get(last.server_id())) {
      throw ClientError(ClientError::Kind::no_daemon, fmt::format("daemon {} went away while building '{}'",
                                                                  last.server_id(), scene));
    }
    if (last.samples_done() != seen_samples || last.state() != seen_state || last.version() != seen_version) {
      seen_samples = last.samples_done();
      seen_state = last.state();
      seen_version = last.version();
      if (progress) progress(last);
    }
  }
  return last;
}

}  // namespace ispars::client
