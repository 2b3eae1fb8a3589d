#include "ispars/server/dds_endpoints.hpp"

#include <fastdds/rtps/common/InstanceHandle.h>
#include <spdlog/spdlog.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>

#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "ispars/server/daemon_inbox.hpp"
#include "ispars/wire/daemon_trust.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/scene_filter.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::server {
namespace fdds = eprosima::fastdds::dds;

namespace {

wire::ParticipantOptions participant_options(const DaemonConfig& c) {
  wire::ParticipantOptions o = c.participant;
  o.name = wire::daemon_participant_name(c.server_id);
  return o;
}

}  // namespace

DdsEndpoints::DdsEndpoints(DaemonInbox& daemon, const DaemonConfig& config, std::uint64_t joined_ms)
    : daemon_(daemon),
      server_id_(config.server_id),
      participant_(participant_options(config)),
      query_type_(new wire::SafeType<msg::QueryRequestPubSubType>()),
      change_type_(new wire::SafeType<msg::ChangeRequestPubSubType>()),
      reply_type_(new wire::SafeType<msg::ReplyPubSubType>()),
      update_type_(new wire::SafeType<msg::UpdateBatchPubSubType>()),
      status_type_(new wire::SafeType<msg::SceneStatusPubSubType>()),
      daemon_type_(new wire::SafeType<msg::DaemonInfoPubSubType>()),
      progress_type_(new wire::SafeType<msg::TourProgressPubSubType>()),
      task_type_(new wire::SafeType<msg::SceneTaskPubSubType>()),
      daemons_seen_([](const msg::DaemonInfo& d) { return d.server_id().to_string(); },
                    // The daemon hears of a new run before the statuses it held back
                    // (SceneClaims orders a daemon's statuses within its run).
                    [this](const msg::DaemonInfo& d) {
                      daemon_.fleet_changed(&d);
                      statuses_.recheck();
                      tasks_seen_.recheck();
                    },
                    // Every announcement is accepted; one of this daemon's id by another
                    // participant is noted (judged per sample, with its own sender: DDS delivers
                    // on several threads, this daemon's own samples among them), unless it is
                    // this process's own participant that a rejoin replaces (same host, pid and
                    // joining time).
                    [this](const msg::DaemonInfo& d, const std::string& sender) {
                      if (d.server_id() != server_id_ || sender == own_identity_) return true;
                      const bool this_process =
                          d.pid() == ::getpid() && d.joined_ms() == joined_ms_ && d.host() == host_;
                      if (!this_process) note_namesake(d, sender);
                      return true;
                    }),
      // A status counts only from the participant that announces the daemon it names: a forged
      // one cannot plant a recipe for a takeover.
      statuses_([](const msg::SceneStatus& s) { return s.scene().to_string(); },
                [this](const msg::SceneStatus& s) { daemon_.status_seen(s); },
                wire::statuses_from_their_daemon(daemons_seen_)),
      // So does a task: a forged one cannot plant POIs in a takeover.
      tasks_seen_([](const msg::SceneTask& t) { return t.scene().to_string() + '/' + std::to_string(t.index()); },
                  [this](const msg::SceneTask& t) { daemon_.task_seen(t); },
                  wire::from_their_daemon<msg::SceneTask>(daemons_seen_)) {
  fdds::DomainParticipant* p = participant_.get();
  own_identity_ = wire::identity_of(p->guid().guidPrefix);
  joined_ms_ = joined_ms;
  host_ = host_name();
  fdds::Topic* query_topic = wire::find_or_create_topic(p, query_type_, wire::kQueryTopic);
  fdds::Topic* change_topic = wire::find_or_create_topic(p, change_type_, wire::kChangeTopic);
  fdds::Topic* reply_topic = wire::find_or_create_topic(p, reply_type_, wire::kReplyTopic);
  fdds::Topic* update_topic = wire::find_or_create_topic(p, update_type_, wire::kUpdatesTopic);
  fdds::Topic* status_topic = wire::find_or_create_topic(p, status_type_, wire::kStatusTopic);
  fdds::Topic* daemon_topic = wire::find_or_create_topic(p, daemon_type_, wire::kDaemonsTopic);
  fdds::Topic* progress_topic = wire::find_or_create_topic(p, progress_type_, wire::kTourProgressTopic);
  fdds::Topic* task_topic = wire::find_or_create_topic(p, task_type_, wire::kTasksTopic);
  fdds::Publisher* pub = wire::created(p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT), "publisher");
  fdds::Subscriber* sub = wire::created(p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT), "subscriber");
  routes_ = std::make_unique<ReplyRoutes>(p, reply_topic, progress_topic, this, server_id_);
  // Each replica's scene filter is evaluated here, per reader: a replica of one scene is sent no
  // other scene's batches (wire/scene_filter.hpp).
  if (!wire::register_scene_filter(p))
    spdlog::warn("the scene filter could not be registered; replicas filter on their side");
  updates_ = wire::created(pub->create_datawriter(update_topic, wire::updates_writer_qos()), "update writer");
  status_ = wire::created(pub->create_datawriter(status_topic, wire::state_writer_qos()), "status writer");
  daemons_ = wire::created(pub->create_datawriter(daemon_topic, wire::state_writer_qos()), "announcement writer");
  daemons_reader_ = wire::created(sub->create_datareader(daemon_topic, wire::state_reader_qos(), &daemons_seen_),
                                  "announcement reader");
  status_reader_ =
      wire::created(sub->create_datareader(status_topic, wire::state_reader_qos(), &statuses_), "status reader");
  tasks_ = wire::created(pub->create_datawriter(task_topic, wire::state_writer_qos()), "task writer");
  tasks_reader_ =
      wire::created(sub->create_datareader(task_topic, wire::state_reader_qos(), &tasks_seen_), "task reader");
  queries_ = wire::created(
      sub->create_datareader(query_topic, wire::request_reply_reader_qos(), this, fdds::StatusMask::data_available()),
      "query reader");
  changes_ = wire::created(
      sub->create_datareader(change_topic, wire::request_reply_reader_qos(), this, fdds::StatusMask::data_available()),
      "change reader");
  // Without DDS Security the daemon delivers nothing inside its process (main.cpp): its probe
  // samples come back through its sockets. Under security its own announcements never came back
  // that way (measured), so there is no probe.
  if (config.participant.security.empty()) probe_ = std::make_unique<SelfProbe>(p, daemon_type_, own_identity_);
  sender_ = std::thread([this] { send_pending_replies(); });
  // A client's route is made as soon as its reply reader is discovered, before its first request.
  participant_.watch_readers([this](const wire::RemoteReader& reader) {
    if (reader.topic != wire::kReplyTopic) return;
    const std::string own = wire::reply_partition(reader.identity);
    if (std::find(reader.partitions.begin(), reader.partitions.end(), own) == reader.partitions.end()) return;
    if (reader.present) {
      routes_->want(reader.identity);
    } else {
      routes_->forget(reader.identity);
    }
    outbox_wake_.notify_all();
  });
}

DdsEndpoints::~DdsEndpoints() {
  participant_.watch_readers({});
  accepting_ = false;
  {
    std::lock_guard lock(outbox_mutex_);
    closing_ = true;
  }
  outbox_wake_.notify_all();
  if (sender_.joinable()) sender_.join();
  // Detach the listeners, then delete the entities while the listener objects still exist.
  if (queries_) queries_->set_listener(nullptr);
  if (changes_) changes_->set_listener(nullptr);
  if (status_reader_) status_reader_->set_listener(nullptr);
  if (tasks_reader_) tasks_reader_->set_listener(nullptr);
  if (daemons_reader_) daemons_reader_->set_listener(nullptr);
  if (probe_) probe_->detach();
  participant_->delete_contained_entities();
}

void DdsEndpoints::stop_requests() { accepting_ = false; }

namespace {

template <class Request>
void take_requests(fdds::DataReader* reader, DaemonInbox& daemon, const std::string& server_id,
                   const std::atomic<bool>& accepting, ReplyRoutes& routes) {
  Request request;
  fdds::SampleInfo info;
  while (reader->take_next_sample(&request, &info) == ReturnCode_t::RETCODE_OK) {
    if (!info.valid_data || !accepting) continue;
    if (request.server_id() != server_id) continue;  // addressed to another daemon
    // The sender is who the transport says, whatever the request claims: replies, retries and
    // the reply cache are keyed by it, so no client can answer, pre-empt or poison another's.
    request.client_id(wire::sender_identity(info));
    routes.want(request.client_id().to_string());  // if its reader was not discovered yet
    daemon.receive(std::move(request));
  }
}

}  // namespace

thread_local bool DdsEndpoints::in_dds_callback = false;

void DdsEndpoints::on_data_available(fdds::DataReader* reader) {
  in_dds_callback = true;
  struct Reset {
    ~Reset() { in_dds_callback = false; }
  } reset;
  if (reader == queries_) {
    take_requests<msg::QueryRequest>(reader, daemon_, server_id_, accepting_, *routes_);
  } else if (reader == changes_) {
    take_requests<msg::ChangeRequest>(reader, daemon_, server_id_, accepting_, *routes_);
  }
}

void DdsEndpoints::on_publication_matched(fdds::DataWriter*, const fdds::PublicationMatchedStatus& info) {
  // The last reader of a route left: release the route (on the sender thread).
  if (info.current_count_change < 0 && info.current_count == 0) {
    routes_->forget(wire::identity_of(info.last_subscription_handle));
  }
  outbox_wake_.notify_all();
}

void DdsEndpoints::send_reply(const msg::Reply& reply, std::chrono::milliseconds wait) {
  // DDS-RPC 1.0 sec. 7.6.2: a reply written before the client's reply reader matched is lost.
  // A reply on a ready route (reply_routes.hpp) goes out at once; others wait (bounded) on the
  // sender thread, so no request thread is held by a client that is slow to match or gone.
  // Replies made inside DDS's own callback (busy refusals, cached replies) always go through the
  // sender thread: creating or waiting for a route there would deadlock with DDS's receive locks.
  const std::string client = reply.client_id().to_string();
  if (!in_dds_callback && routes_->ready(client)) {
    write_reply(reply);
    return;
  }
  {
    std::lock_guard lock(outbox_mutex_);
    if (outbox_.size() >= kMaxOutbox) {
      spdlog::warn("reply outbox full ({} replies); dropping the reply to {} #{} (it will retry)", outbox_.size(),
                   client, reply.request_seq());
      return;
    }
    outbox_.push_back({reply, std::chrono::steady_clock::now() + wait});
  }
  outbox_wake_.notify_all();
}

void DdsEndpoints::write_reply(const msg::Reply& reply) {
  if (!routes_->write_reply(reply))
    spdlog::error("reply to {} #{} could not be written", reply.client_id(), reply.request_seq());
}

void DdsEndpoints::send_pending_replies() {
  bool handshaking = false;
  std::unique_lock lock(outbox_mutex_);
  while (!closing_) {
    // A handshake waits for an acknowledgement, which calls nothing: poll it every 2 ms.
    outbox_wake_.wait_for(lock, std::chrono::milliseconds(handshaking ? 2 : 20),
                          [&] { return closing_ || !outbox_.empty() || routes_->has_work(); });
    std::list<PendingReply> pending;
    pending.splice(pending.end(), outbox_);
    lock.unlock();  // into DDS without outbox_mutex_: DDS's callbacks queue replies under it
    for (auto& item : pending) {
      if (!routes_->has(item.reply.client_id().to_string())) routes_->want(item.reply.client_id().to_string());
    }
    handshaking = routes_->service();
    const auto now = std::chrono::steady_clock::now();
    for (auto it = pending.begin(); it != pending.end();) {
      const std::string client = it->reply.client_id().to_string();
      const bool ready = routes_->ready(client);
      if (ready || now >= it->deadline) {
        if (!ready)
          spdlog::warn("client {}'s reply reader has not acknowledged its route; replying anyway (it will retry)",
                       client);
        write_reply(it->reply);
        it = pending.erase(it);
      } else {
        ++it;
      }
    }
    lock.lock();
    outbox_.splice(outbox_.begin(), pending);  // still waiting for their reader, ahead of newer ones
  }
}

void DdsEndpoints::publish_update(const msg::UpdateBatch& batch) {
  msg::UpdateBatch copy = batch;
  if (!updates_->write(&copy))
    spdlog::error("update {}..{} of {} could not be written", batch.from_version(), batch.to_version(), batch.scene());
}

void DdsEndpoints::retire_updates(const std::string& scene) {
  msg::UpdateBatch key;
  key.scene(scene);
  // The handle is computed from the key (Fast DDS 2.9 has no lookup_instance); a scene never
  // published here has no instance, and then there is nothing to dispose.
  if (updates_->dispose(&key, fdds::HANDLE_NIL) != ReturnCode_t::RETCODE_OK) {
    spdlog::debug("no updates of {} to dispose", scene);
    return;
  }
  // Unregistered, the instance's kept batches leave the writer's history: a late joiner gets none.
  if (updates_->unregister_instance(&key, fdds::HANDLE_NIL) != ReturnCode_t::RETCODE_OK) {
    spdlog::warn("the updates of {} were disposed but not unregistered", scene);
  }
  spdlog::debug("updates of {} disposed", scene);
}

void DdsEndpoints::publish_status(const msg::SceneStatus& status) {
  msg::SceneStatus copy = status;
  if (!status_->write(&copy)) spdlog::error("status of {} could not be written", status.scene());
}

void DdsEndpoints::publish_tasks(const std::string& scene, std::uint64_t generation, std::uint64_t events,
                                 const std::function<std::vector<msg::SceneTask>()>& tasks) {
  std::lock_guard lock(tasks_mutex_);
  auto& last = tasks_published_[scene];
  if (last == std::pair(generation, events)) return;
  for (msg::SceneTask& t : tasks()) {
    if (!tasks_->write(&t)) spdlog::error("task {} of {} could not be written", t.index(), scene);
  }
  last = {generation, events};
}

void DdsEndpoints::announce(const msg::DaemonInfo& info) {
  msg::DaemonInfo copy = info;
  if (!daemons_->write(&copy)) spdlog::error("announcement could not be written");
}

void DdsEndpoints::publish_tour_progress(const msg::TourProgress& progress) {
  routes_->write_progress(progress);  // advisory: a lost one is replaced by the next
}

void DdsEndpoints::note_namesake(const msg::DaemonInfo& other, const std::string& sender) {
  id_elsewhere_ = true;
  // A joining time before 2024 or a day ahead of this clock is no time (a machine without a
  // real-time clock, or a forged announcement): such a namesake never counts as the older one.
  constexpr std::uint64_t kEarliest = 1'704'067'200'000;  // 2024-01-01
  constexpr std::uint64_t kSkew = 86'400'000;
  const bool plausible = other.joined_ms() >= kEarliest && other.joined_ms() <= joined_ms_ + kSkew;
  const bool other_is_older =
      plausible && (other.joined_ms() < joined_ms_ || (other.joined_ms() == joined_ms_ && sender < own_identity_));
  if (!other_is_older) {
    id_contested_ = true;  // this one stays: re-announce so that readers keep it as the latest
    return;
  }
  std::lock_guard lock(namesake_mutex_);
  older_namesake_ = fmt::format("host {}, pid {}", other.host().to_string(), other.pid());
}

std::uint64_t DdsEndpoints::update_subscribers() const {
  fdds::PublicationMatchedStatus matched;
  if (updates_->get_publication_matched_status(matched) != ReturnCode_t::RETCODE_OK) return 0;
  return static_cast<std::uint64_t>(std::max(0, matched.current_count));
}

std::uint64_t DdsEndpoints::reply_clients() const { return routes_->ready_count(); }

std::uint64_t DdsEndpoints::reply_routes() const { return routes_->size(); }

std::string DdsEndpoints::older_namesake() const {
  std::lock_guard lock(namesake_mutex_);
  return older_namesake_;
}

std::vector<msg::DaemonInfo> DdsEndpoints::other_daemons() const {
  std::vector<msg::DaemonInfo> out = daemons_seen_.all();
  std::erase_if(out, [&](const msg::DaemonInfo& d) { return d.server_id() == server_id_; });
  return out;
}

}  // namespace ispars::server
