#include "ispars/client/replica.hpp"

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/wire/convert.hpp"
#include "replica_inbox.hpp"

namespace ispars::client {
// The replica's own thread applies the batches its inbox (replica_inbox.hpp) queued, and resyncs
// when they show a gap, another roadmap or a rejoin, or the owner's status shows it behind.
class RoadmapReplica::Impl {
 public:
  // Why a snapshot is taken (ReplicaResyncs counts each); none: it need not be.
  enum class Resync { none, first, gap, moved, lag, rejoin };

  Impl(Client& client, std::string scene, std::function<void(const ReplicaEvent&)> on_change, ReplicaLimits limits)
      : client_(client),
        scene_(std::move(scene)),
        on_change_(std::move(on_change)),
        limits_(checked_limits(limits)),
        inbox_(client_, scene_, limits_) {
    thread_ = std::thread([this] { run(); });
  }

  ~Impl() {
    inbox_.stop();
    thread_.join();
  }

  void run() {
    // Wait until the update reader has matched a writer, so no batch after the snapshot is missed.
    (void)inbox_.wait_matched(std::chrono::seconds(4));
    Resync need_sync = Resync::first;
    while (!inbox_.stopping()) {
      if (inbox_.take_rejoined()) need_sync = Resync::rejoin;  // the client's new participant: batches may be missing
      if (need_sync != Resync::none) {
        if (resync(need_sync)) need_sync = Resync::none;
        if (need_sync != Resync::none) {
          (void)inbox_.pause(std::chrono::milliseconds(500));
          continue;
        }
      }
      const std::deque<msg::UpdateBatch> batches = inbox_.take(kStatusPeriod);
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
  // of the replica's for the lag limit (a batch was lost, and an idle owner writes no other), or
  // at the replica's version it has held other POIs for that long (a task that needed no vertex,
  // say one merged in after a partition healed, whose batch this replica never saw).
  // `quiet`: no batch arrived since the last look (a replica busy applying batches is not behind).
  // Why it must resync, or none.
  Resync behind_owner(bool quiet) {
    std::string owner;
    std::uint64_t generation = 0, version = 0;
    std::size_t pois = 0;
    {
      std::lock_guard lock(state_mutex_);
      if (snapshots_ == 0) return Resync::none;
      owner = owner_;
      generation = generation_;
      version = roadmap_.version();
      pois = roadmap_.poi_count();
    }
    const auto status = client_.latest_status(scene_);
    if (!status || status->state == SceneState::unloaded || status->state == SceneState::empty) return Resync::none;
    // Holding nothing (a snapshot of a scene just claimed, before its roadmap was published)
    // while the status shows a built roadmap.
    if (generation == 0) return status->generation != 0 ? Resync::first : Resync::none;
    if (status->server_id != owner || status->generation != generation) return Resync::moved;
    const auto now = std::chrono::steady_clock::now();
    const bool behind = status->version > version || (status->version == version && status->poi_count != pois);
    if (!quiet || !behind) {
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
    // ReplicaResyncs' counter of each Resync, in the enum's order.
    static constexpr std::size_t ReplicaResyncs::*kCounters[] = {nullptr,
                                                                 &ReplicaResyncs::first,
                                                                 &ReplicaResyncs::gap,
                                                                 &ReplicaResyncs::moved,
                                                                 &ReplicaResyncs::lag,
                                                                 &ReplicaResyncs::rejoin};
    if (why != Resync::none) ++(resyncs_.*kCounters[static_cast<std::size_t>(why)]);
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
  // The replica's thread's: the last resync behind_owner() asked for, and since when the owner's
  // status has shown a later version than this replica's.
  std::chrono::steady_clock::time_point moved_at_{};
  std::optional<std::chrono::steady_clock::time_point> lag_since_;
  static constexpr std::chrono::milliseconds kStatusPeriod{100};  // how often the status is looked at
  ReplicaInbox inbox_;
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
std::size_t RoadmapReplica::batches_of_other_scenes() const { return impl_->inbox_.other_scenes(); }
ReplicaResyncs RoadmapReplica::resyncs() const {
  std::lock_guard lock(impl_->state_mutex_);
  return impl_->resyncs_;
}
std::size_t RoadmapReplica::batches_dropped() const { return impl_->inbox_.dropped(); }
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
