#pragma once
// The daemon's link to the domain: its DDS endpoints, replaced whole when the daemon rejoins.
// Rejoining: a peer this daemon dropped came back under the same GUID (DDS Security: the session
// between them may never recover, PeerWatch), or this daemon stood still past its peers' lease;
// a new participant is made beside the old one, announces the daemon and publishes its statuses
// again, and the old one, answering no requests, leaves once the daemons it heard hear the new one.

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <shared_mutex>
#include <string>
#include <vector>

#include "ispars/server/daemon_config.hpp"
#include "ispars/server/daemon_outbox.hpp"
#include "ispars/wire/rejoin_schedule.hpp"

namespace ispars::server {

class DdsEndpoints;
class StopSignal;

/// The participant of the moment, behind a lock that a rejoin holds alone only to swap it.
class DdsLink final : public DaemonOutbox {
 public:
  /// Makes a participant with its endpoints (each rejoin makes a new one); may throw.
  using Factory = std::function<std::unique_ptr<DdsEndpoints>()>;
  /// What a new participant must say at once: the daemon's announcement, and every held
  /// scene's status and version (StatusPublisher::republish).
  struct Hooks {
    std::function<void()> announce;
    std::function<void()> republish;
  };

  DdsLink(const DaemonConfig& config, Factory make, StopSignal& stop);
  ~DdsLink() override;
  DdsLink(const DdsLink&) = delete;
  DdsLink& operator=(const DdsLink&) = delete;

  /// Joins the domain with the first participant; throws on DDS setup failure.
  void open();
  /// Set once, before the fleet thread runs (it is the one that rejoins).
  void set_hooks(Hooks hooks) { hooks_ = std::move(hooks); }
  /// Deletes the participant (the stop's last DDS step); later calls are no-ops.
  void close();

  /// Runs `f` on the endpoints of the moment, under the shared lock; nothing when closed. Never
  /// held while a participant is made or deleted (whose callbacks may be waiting for it).
  template <class F>
  void with(F&& f) const {
    std::shared_lock lock(mutex_);
    if (endpoints_) f(*endpoints_);
  }
  [[nodiscard]] std::vector<msg::DaemonInfo> other_daemons() const;

  /// The health watchdog saw this process stand still for `ms` (SIGSTOP, a stalled machine).
  void note_stood_still(std::int64_t ms) { stood_still_ms_ = ms; }
  /// On the fleet thread each pass: rejoins after standing still, or (under DDS Security) when
  /// the rejoin schedule says a returned peer needs it.
  void rejoin_if_due();

  void send_reply(const msg::Reply& reply) override;
  void publish_tour_progress(const msg::TourProgress& progress) override;
  void publish_update(const msg::UpdateBatch& batch) override;
  void retire_updates(const std::string& scene) override;
  void publish_status(const msg::SceneStatus& status) override;
  void publish_tasks(const std::string& scene, std::uint64_t generation, std::uint64_t events,
                     const std::function<std::vector<msg::SceneTask>()>& tasks) override;

 private:
  void rejoin(const std::string& why);
  /// Keeps the old participant beside the new one until the new one has heard every daemon in
  /// `heard`; false if it had not when the overlap ran out.
  bool overlap_until_heard(const std::vector<std::string>& heard);

  const DaemonConfig& config_;
  Factory make_;
  StopSignal& stop_;
  Hooks hooks_;
  mutable std::shared_mutex mutex_;
  std::unique_ptr<DdsEndpoints> endpoints_;
  wire::RejoinSchedule schedule_{std::chrono::seconds(30), std::chrono::seconds(10)};  // the fleet thread's
  std::atomic<std::int64_t> stood_still_ms_{0};                                        // 0: not since the last rejoin
};

}  // namespace ispars::server
