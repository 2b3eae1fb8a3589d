#include "ispars/client/replica.hpp"

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>

#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/wire/convert.hpp"
#include "ispars/wire/identity.hpp"
#include "ispars/wire/participant.hpp"
#include "ispars/wire/safe_type.hpp"
#include "ispars/wire/scene_filter.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace ispars::client {
namespace fdds = eprosima::fastdds::dds;

// DDS delivers updates on its receive thread, which must never block (a snapshot request made
// there would wait for a reply that same thread has to deliver). The listener only queues; the
// replica's own thread applies batches and resyncs.
//
// Its update reader lives on the client's participant (a ParticipantUser): when the client
// rejoins the domain, the reader is made again on the new participant and the replica resyncs.
class RoadmapReplica::Impl final : public fdds::DataReaderListener, public ParticipantUser {
 public:
  // Why a snapshot is taken (ReplicaResyncs counts each); none: it need not be.
  enum class Resync { none, first, gap, moved, lag, rejoin };

  Impl(Client& client, std::string scene, std::function<void(const ReplicaEvent&)> on_change, ReplicaLimits limits)
      : client_(client),
        scene_(std::move(scene)),
        on_change_(std::move(on_change)),
        limits_(checked(limits)),
        type_(new wire::SafeType<msg::UpdateBatchPubSubType>()) {
    client_.add_participant_user(*this);  // attach(): throws when the reader cannot be made
    thread_ = std::thread([this] { run(); });
  }

  ~Impl() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    thread_.join();
    client_.remove_participant_user(*this);
  }

  void attach(wire::Participant& participant) override {
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
        subscriber->create_datareader(filtered, wire::updates_reader_qos(), this, fdds::StatusMask::data_available());
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

  void detach(wire::Participant& participant) override {
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
    subscriber->delete_datareader(reader);
    participant->delete_subscriber(subscriber);
    participant->delete_contentfilteredtopic(filtered);
  }

  // Whether the update reader has matched a writer (false while detached).
  bool matched() {
    std::lock_guard lock(mutex_);
    if (!reader_) return false;
    fdds::SubscriptionMatchedStatus status;
    reader_->get_subscription_matched_status(status);
    return status.current_count > 0;
  }

  void on_data_available(fdds::DataReader* reader) override {
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

  static ReplicaLimits checked(const ReplicaLimits& limits) {
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

  static std::size_t payload_bytes(const msg::UpdateBatch& b) {
    return b.order().size() + b.vertices().size() * sizeof(msg::Vertex) + b.edges().size() * sizeof(msg::Edge);
  }

  // With mutex_ held. Queues `batch`, then drops the oldest queued batches past the limits (never
  // the newest): the next batch applied then shows a gap, and the replica resyncs.
  void queue(msg::UpdateBatch batch) {
    inbox_bytes_ += payload_bytes(batch);
    inbox_.push_back(std::move(batch));
    while (inbox_.size() > 1 && (inbox_.size() > limits_.batches || inbox_bytes_ > limits_.bytes)) {
      inbox_bytes_ -= payload_bytes(inbox_.front());
      inbox_.pop_front();
      ++dropped_;
    }
  }

  void run() {
    // Wait until the update reader has matched a writer, so no batch after the snapshot is missed.
    for (int i = 0; i < 400 && !stopping() && !matched(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    Resync need_sync = Resync::first;
    while (!stopping()) {
      if (take_rejoined()) need_sync = Resync::rejoin;  // the client's new participant: batches may be missing
      if (need_sync != Resync::none) {
        if (resync(need_sync)) need_sync = Resync::none;
        if (need_sync != Resync::none) {
          std::unique_lock lock(mutex_);
          wake_.wait_for(lock, std::chrono::milliseconds(500), [&] { return stopping_; });
          continue;
        }
      }
      std::deque<msg::UpdateBatch> batches;
      {
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, kStatusPeriod, [&] { return stopping_ || !inbox_.empty(); });
        batches.swap(inbox_);
        inbox_bytes_ = 0;
      }
      if (owner_dropped_or_unloaded()) {
        forget_roadmap();
        need_sync = Resync::first;  // a later build or load brings it back
        continue;
      }
      // At most once a second: while two daemons still both hold the scene their statuses alternate.
      if (std::chrono::steady_clock::now() - moved_at_ > std::chrono::seconds(1)) {
        if (const Resync behind = behind_owner(batches.empty()); behind != Resync::none) {
          moved_at_ = std::chrono::steady_clock::now();
          lag_since_.reset();
          need_sync = behind;  // no batch may come to say so (the owner is idle)
          continue;
        }
      }
      for (const msg::UpdateBatch& b : batches) {
        need_sync = apply(b);
        if (need_sync != Resync::none) break;
      }
    }
  }

  bool stopping() {
    std::lock_guard lock(mutex_);
    return stopping_;
  }

  bool take_rejoined() {
    std::lock_guard lock(mutex_);
    return std::exchange(rejoined_, false);
  }

  // Takes a snapshot (counted under `why`), then applies every queued batch after it. False when
  // it failed.
  bool resync(Resync why) {
    try {
      Snapshot s = client_.snapshot(scene_);
      {
        std::lock_guard lock(state_mutex_);
        if (generation_ != 0 && generation_ != s.generation) retired_.insert(generation_);
        roadmap_ = std::move(s.roadmap);
        generation_ = s.generation;
        owner_ = s.status.server_id;
        root_ = s.root;
        pois_ = std::move(s.pois);
        ++snapshots_;
        count(why);
        last_error_.clear();
        samples_ = s.status.samples_done;
      }
      state_changed_.notify_all();
      notify(true);
      return true;
    } catch (const std::exception& e) {
      std::lock_guard lock(state_mutex_);
      last_error_ = e.what();
      return false;
    }
  }

  // Whether the daemon this replica follows says the roadmap it holds is gone: its status (as
  // believed: only from that daemon) is EMPTY (dropped) or UNLOADED.
  bool owner_dropped_or_unloaded() {
    std::string owner;
    {
      std::lock_guard lock(state_mutex_);
      if (generation_ == 0) return false;  // holds no built roadmap
      owner = owner_;
    }
    const auto status = client_.latest_status(scene_);
    return status && status->server_id == owner &&
           (status->state == SceneState::empty || status->state == SceneState::unloaded);
  }

  // Whether this replica must resync although no batch says so, as the scene's status (believed
  // only from the daemon it names) shows: it is another daemon's than the one this replica copied,
  // or of another roadmap (the fleet moved the scene, say to the fresher of two holders after a
  // partition healed, and this replica may hold the loser's copy), or its version has been ahead
  // of the replica's for the lag limit (a batch was lost, and an idle owner writes no other).
  // `quiet`: no batch arrived since the last look (a replica busy applying batches is not behind).
  // Why it must resync, or none.
  Resync behind_owner(bool quiet) {
    std::string owner;
    std::uint64_t generation = 0, version = 0;
    {
      std::lock_guard lock(state_mutex_);
      if (snapshots_ == 0) return Resync::none;
      owner = owner_;
      generation = generation_;
      version = roadmap_.version();
    }
    const auto status = client_.latest_status(scene_);
    if (!status || status->state == SceneState::unloaded || status->state == SceneState::empty) return Resync::none;
    // Holding nothing (a snapshot of a scene just claimed, before its roadmap was published)
    // while the status shows a built roadmap.
    if (generation == 0) return status->generation != 0 ? Resync::first : Resync::none;
    if (status->server_id != owner || status->generation != generation) return Resync::moved;
    const auto now = std::chrono::steady_clock::now();
    if (!quiet || status->version <= version) {
      lag_since_.reset();
      return Resync::none;
    }
    if (!lag_since_) lag_since_ = now;
    return now - *lag_since_ >= limits_.lag ? Resync::lag : Resync::none;
  }

  // The roadmap was dropped or its scene unloaded: the copy is no longer what any daemon serves.
  void forget_roadmap() {
    {
      std::lock_guard lock(state_mutex_);
      if (generation_ != 0) retired_.insert(generation_);
      roadmap_ = Roadmap(pois_.size());
      generation_ = 0;
      samples_ = 0;
      ++retirements_;
      last_error_ = "the roadmap of scene '" + scene_ + "' was dropped or unloaded on daemon " + owner_;
    }
    state_changed_.notify_all();
    notify(true);
  }

  // Applies one batch; why the replica must resync instead (a gap, another generation), or none.
  Resync apply(const msg::UpdateBatch& b) {
    {
      std::lock_guard lock(state_mutex_);
      if (retired_.count(b.generation()) > 0) return Resync::none;  // a late batch of a replaced roadmap
      // Another roadmap (a rebuild) or another publisher (the scene moved): resync from the owner.
      if (b.generation() != generation_ || b.server_id() != owner_) return Resync::moved;
      // A task added POIs, which the vertices held here may see too: only a snapshot tells.
      if (b.poi_count() > roadmap_.poi_count()) return Resync::moved;
      const std::uint64_t version = roadmap_.version();
      if (b.to_version() <= version) return Resync::none;  // already in the snapshot: a duplicate
      if (b.from_version() != version) return Resync::gap;
      try {
        apply_batch(roadmap_, wire::from_message(b));
      } catch (const std::runtime_error& e) {
        last_error_ = e.what();
        return Resync::gap;
      }
      ++batches_;
      samples_ = b.samples_done();
    }
    state_changed_.notify_all();
    notify(false);
    return Resync::none;
  }

  // With state_mutex_ held.
  void count(Resync why) {
    switch (why) {
      case Resync::none:
        break;
      case Resync::first:
        ++resyncs_.first;
        break;
      case Resync::gap:
        ++resyncs_.gap;
        break;
      case Resync::moved:
        ++resyncs_.moved;
        break;
      case Resync::lag:
        ++resyncs_.lag;
        break;
      case Resync::rejoin:
        ++resyncs_.rejoin;
        break;
    }
  }

  void notify(bool resynced) {
    if (!on_change_) return;
    ReplicaEvent event;
    {
      std::lock_guard lock(state_mutex_);
      event = {generation_, roadmap_.version(), roadmap_.vertex_count(), roadmap_.edge_count(), samples_, resynced};
    }
    on_change_(event);
  }

  Client& client_;
  const std::string scene_;
  const std::function<void(const ReplicaEvent&)> on_change_;
  const ReplicaLimits limits_;
  fdds::TypeSupport type_;

  std::mutex mutex_;  // the reader, the inbox and stopping
  fdds::Subscriber* subscriber_ = nullptr;
  fdds::DataReader* reader_ = nullptr;
  fdds::ContentFilteredTopic* filtered_ = nullptr;
  std::atomic<std::size_t> other_scenes_{0};  // batches of other scenes that reached the reader
  std::size_t attached_ = 0;                  // participants attached to so far
  bool rejoined_ = false;                     // attached to a new participant since the last look
  // The replica's thread's: the last resync behind_owner() asked for, and since when the owner's
  // status has shown a later version than this replica's.
  std::chrono::steady_clock::time_point moved_at_{};
  std::optional<std::chrono::steady_clock::time_point> lag_since_;
  std::condition_variable wake_;
  std::deque<msg::UpdateBatch> inbox_;
  std::size_t inbox_bytes_ = 0;
  std::size_t dropped_ = 0;                                       // batches dropped from a full inbox
  static constexpr std::chrono::milliseconds kStatusPeriod{100};  // how often the status is looked at
  bool stopping_ = false;
  std::thread thread_;

  mutable std::mutex state_mutex_;  // the replica itself
  mutable std::condition_variable state_changed_;
  Roadmap roadmap_;
  std::uint64_t generation_ = 0;
  std::set<std::uint64_t> retired_;  // generations this replica has left behind
  std::string owner_;
  std::uint64_t samples_ = 0;
  Vec3 root_ = Vec3::Zero();
  std::vector<Vec3> pois_;
  std::size_t snapshots_ = 0;
  std::size_t batches_ = 0;
  std::size_t retirements_ = 0;
  ReplicaResyncs resyncs_;
  std::string last_error_;
};

RoadmapReplica::RoadmapReplica(Client& client, std::string scene, std::function<void(const ReplicaEvent&)> on_change,
                               ReplicaLimits limits)
    : impl_(std::make_unique<Impl>(client, std::move(scene), std::move(on_change), limits)) {}
RoadmapReplica::~RoadmapReplica() = default;

Roadmap RoadmapReplica::roadmap() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->roadmap_;
}
void RoadmapReplica::read(const std::function<void(const Roadmap&, std::uint64_t, std::uint64_t)>& read) const {
  std::lock_guard lock(impl_->state_mutex_);
  read(impl_->roadmap_, impl_->generation_, impl_->samples_);
}
std::uint64_t RoadmapReplica::version() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->roadmap_.version();
}
std::uint64_t RoadmapReplica::generation() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->generation_;
}
std::size_t RoadmapReplica::retirements() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->retirements_;
}
std::size_t RoadmapReplica::snapshots_taken() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->snapshots_;
}
std::size_t RoadmapReplica::batches_applied() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->batches_;
}
std::size_t RoadmapReplica::batches_of_other_scenes() const { return impl_->other_scenes_.load(); }
ReplicaResyncs RoadmapReplica::resyncs() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->resyncs_;
}
std::size_t RoadmapReplica::batches_dropped() const {
  std::lock_guard lock(impl_->mutex_);
  return impl_->dropped_;
}
Vec3 RoadmapReplica::root() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->root_;
}
std::vector<Vec3> RoadmapReplica::pois() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->pois_;
}
std::string RoadmapReplica::last_error() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->last_error_;
}
bool RoadmapReplica::wait_for(std::uint64_t generation, std::uint64_t version,
                              std::chrono::milliseconds timeout) const {
  std::unique_lock lock(impl_->state_mutex_);
  return impl_->state_changed_.wait_for(lock, timeout, [&] {
    return impl_->snapshots_ > 0 && (generation == 0 || impl_->generation_ == generation) &&
           impl_->roadmap_.version() >= version;
  });
}

}  // namespace ispars::client
