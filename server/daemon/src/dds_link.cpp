// isparsd rejoining its DDS domain with a new participant, under DDS Security. A peer (daemon or
// client) this one dropped (its lease ran out here), then discovered again under the same GUID,
// and which has not authenticated again within a grace (wire::RejoinSchedule) kept running: it
// stalled or the link was cut one way. A daemon whose first handshake with this one never ended
// (a Fast DDS 2.9.1 fault) makes one rejoin too. The sessions between the two may never recover: Debian's
// Fast DDS 2.9.1 cannot authenticate a peer again while the other side keeps its DDS Security
// session. A new participant (a new GUID) meets every peer afresh. The daemon keeps its scenes,
// claims and jobs; it announces itself and publishes each scene's status again from the new
// participant while the old one, answering no requests, still announces it; the old one leaves
// once the daemons it heard have heard the new one. Meanwhile the fleet thread does not apply the
// fleet's rule (it does not take the scenes of daemons it has not heard yet). Replicas see a new
// update writer and resync.

#include "ispars/server/dds_link.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <mutex>
#include <utility>

#include "ispars/server/dds_endpoints.hpp"
#include "ispars/server/stop_signal.hpp"

namespace ispars::server {
namespace {

// How long after rejoining the fleet's rule waits (at least): under DDS Security a handshake
// takes a few hundred milliseconds per peer.
constexpr std::chrono::milliseconds kRejoinListen{3000};
// How long the old participant stays, at most, while the daemons it heard have not heard the new one.
constexpr std::chrono::milliseconds kRejoinOverlap{15000};

}  // namespace

DdsLink::DdsLink(const DaemonConfig& config, Factory make, StopSignal& stop)
    : config_(config), make_(std::move(make)), stop_(stop) {}

DdsLink::~DdsLink() { close(); }

void DdsLink::open() {
  auto first = make_();
  std::unique_lock lock(mutex_);
  endpoints_ = std::move(first);
}

void DdsLink::close() {
  std::unique_ptr<DdsEndpoints> gone;
  {
    std::unique_lock lock(mutex_);
    gone = std::move(endpoints_);
  }
  gone.reset();  // outside the lock: its callbacks may be waiting for it
}

std::vector<msg::DaemonInfo> DdsLink::other_daemons() const {
  std::vector<msg::DaemonInfo> out;
  with([&](DdsEndpoints& d) { out = d.other_daemons(); });
  return out;
}

void DdsLink::send_reply(const msg::Reply& reply) {
  with([&](DdsEndpoints& d) { d.send_reply(reply); });
}
void DdsLink::publish_tour_progress(const msg::TourProgress& progress) {
  with([&](DdsEndpoints& d) { d.publish_tour_progress(progress); });
}
void DdsLink::publish_update(const msg::UpdateBatch& batch) {
  with([&](DdsEndpoints& d) { d.publish_update(batch); });
}
void DdsLink::retire_updates(const std::string& scene) {
  with([&](DdsEndpoints& d) { d.retire_updates(scene); });
}
void DdsLink::publish_status(const msg::SceneStatus& status) {
  with([&](DdsEndpoints& d) { d.publish_status(status); });
}
void DdsLink::publish_tasks(const std::string& scene, std::uint64_t generation, std::uint64_t events,
                            const std::function<std::vector<msg::SceneTask>()>& tasks) {
  with([&](DdsEndpoints& d) { d.publish_tasks(scene, generation, events, tasks); });
}

void DdsLink::rejoin_if_due() {
  // Only under DDS Security, whose sessions are what cannot be made again: without it Fast DDS
  // meets a returning peer by itself (PartitionTest, plain), and a rejoin would only make churn
  // (a plain 10-round partition run with rejoins left its replica behind in round 6). A client
  // counts too: a replica this daemon dropped can no more be authenticated again than a daemon,
  // and a new participant here gives it a fresh session.
  if (const std::int64_t ms = stood_still_ms_.exchange(0); ms > 0) {
    // Its peers dropped it, and it kept their sessions: a peer that dropped a participant and
    // meets it again under the same GUID may never hear what it writes, nor it theirs (plain DDS
    // too: HistoryTest, SIGSTOP past the lease, left two daemons holding one scene, each missing
    // the other's announcement, for good). A new participant meets every peer afresh.
    rejoin(
        fmt::format("this daemon stood still for {:.1f} s (stopped, or its machine stalled), past its peers' "
                    "lease of {} s",
                    static_cast<double>(ms) / 1000.0,
                    wire::lease_seconds(config_.participant.lease_seconds, !config_.participant.security.empty())));
    return;
  }
  if (config_.participant.security.empty()) return;
  wire::RejoinSchedule::Decision decision;
  with([&](DdsEndpoints& d) { decision = schedule_.poll(d.peers(), std::chrono::steady_clock::now()); });
  if (decision.given_up) {
    spdlog::warn(
        "{} did not authenticate with this daemon's participant before the last rejoin either; no "
        "rejoin is made for it again (it may lack DDS Security)",
        decision.given_up->name);
  }
  if (decision.deferred) {
    spdlog::warn(
        "{}; rejoined {:.0f} s ago, so again {:.0f} s after that unless it authenticates, leaves or "
        "rejoins itself meanwhile",
        schedule_.reason(*decision.deferred), std::chrono::duration<double>(decision.since_last).count(),
        std::chrono::duration<double>(schedule_.period()).count());
  }
  if (decision.now) rejoin(schedule_.reason(*decision.now));
}

void DdsLink::rejoin(const std::string& why) {
  const auto start = std::chrono::steady_clock::now();
  spdlog::warn("rejoining DDS domain {} with a new participant: {}", config_.participant.domain, why);
  // Made before the old one leaves (a rejoin is not a leave): peers that meet the new participant
  // while the old one still announces this daemon never see it gone, so none of them takes its
  // scenes over (read as "left while holding" when the old one left first: CI, 2026-11-27).
  std::unique_ptr<DdsEndpoints> old;
  try {
    auto fresh = make_();
    std::unique_lock lock(mutex_);
    old = std::move(endpoints_);
    endpoints_ = std::move(fresh);
  } catch (const std::exception& e) {
    spdlog::error("rejoining DDS domain {} failed: {}; the old participant stays, trying again in {:.0f} s",
                  config_.participant.domain, e.what(), std::chrono::duration<double>(schedule_.period()).count());
    return;
  }
  std::vector<std::string> heard;  // the daemons the old participant heard, which must hear the new one
  if (old) {
    old->stop_requests();  // requests are answered by the new participant alone
    for (const msg::DaemonInfo& d : old->other_daemons()) heard.push_back(d.server_id().to_string());
  }
  if (hooks_.announce) hooks_.announce();
  if (hooks_.republish) hooks_.republish();
  const bool all_heard = overlap_until_heard(heard);
  old.reset();                             // peers see the old participant leave, and keep the new one's announcement
  if (hooks_.announce) hooks_.announce();  // the latest announcement everywhere is the new participant's
  spdlog::info("rejoined DDS domain {} in {:.2f} s; {} other daemons heard{}", config_.participant.domain,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), other_daemons().size(),
               all_heard ? "" : " (not every daemon the old participant heard)");
}

bool DdsLink::overlap_until_heard(const std::vector<std::string>& heard) {
  // At least kRejoinListen (the fleet's rule waits as long: it must not take the scenes of daemons
  // not heard yet), then until the new participant hears every daemon the old one heard, at most
  // kRejoinOverlap. A daemon heard has authenticated the new participant, and its announcement
  // reader has matched the new writer or does within milliseconds. Interrupted by a stop.
  const auto start = std::chrono::steady_clock::now();
  const auto listen = std::max(kRejoinListen, std::chrono::milliseconds(config_.discovery_wait_ms));
  const auto all_heard = [&] {
    const std::vector<msg::DaemonInfo> now = other_daemons();
    return std::all_of(heard.begin(), heard.end(), [&](const std::string& id) {
      return std::any_of(now.begin(), now.end(), [&](const msg::DaemonInfo& d) { return d.server_id() == id; });
    });
  };
  while (!stop_.stopped()) {
    const auto elapsed = std::chrono::steady_clock::now() - start;
    if (elapsed >= kRejoinOverlap) break;
    if (elapsed >= listen && all_heard()) return true;
    if (!stop_.idle_for(std::chrono::milliseconds(100))) break;
  }
  return all_heard();
}

}  // namespace ispars::server
