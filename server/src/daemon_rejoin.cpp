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

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "daemon.hpp"
#include "dds_endpoints.hpp"

namespace ispars::server {
namespace {

// How long after rejoining the fleet's rule waits (at least): under DDS Security a handshake
// takes a few hundred milliseconds per peer.
constexpr std::chrono::milliseconds kRejoinListen{3000};
// How long the old participant stays, at most, while the daemons it heard have not heard the new one.
constexpr std::chrono::milliseconds kRejoinOverlap{15000};

}  // namespace

std::vector<msg::DaemonInfo> Daemon::other_daemons() const {
  std::vector<msg::DaemonInfo> out;
  with_dds([&](DdsEndpoints& d) { out = d.other_daemons(); });
  return out;
}

void Daemon::rejoin_if_a_peer_returned() {
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
                    static_cast<double>(ms) / 1000.0, wire::kLeaseSeconds));
    return;
  }
  if (config_.security.empty()) return;
  wire::RejoinSchedule::Decision decision;
  with_dds([&](DdsEndpoints& d) { decision = rejoin_schedule_.poll(d.peers(), std::chrono::steady_clock::now()); });
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
        rejoin_schedule_.reason(*decision.deferred), std::chrono::duration<double>(decision.since_last).count(),
        std::chrono::duration<double>(rejoin_schedule_.period()).count());
  }
  if (decision.now) rejoin(rejoin_schedule_.reason(*decision.now));
}

void Daemon::mark_version(const std::string& scene, const RoadmapSession& session) {
  // The new update writer keeps none of the batches the old one wrote: a replica that missed the
  // last of them would hear nothing that tells it. An empty batch at the roadmap's version does:
  // one behind sees a gap and resyncs; one up to date takes it for a duplicate.
  const SessionStatus status = session.status();
  if (!status.recipe) return;
  msg::UpdateBatch mark;
  mark.scene(scene);
  mark.server_id(config_.server_id);
  mark.generation(session.published().generation);
  mark.from_version(status.version);
  mark.to_version(status.version);
  mark.samples_done(status.samples_done);
  mark.first_edge(static_cast<std::uint32_t>(status.edges));
  with_dds([&](DdsEndpoints& d) { d.publish_update(mark); });
}

void Daemon::rejoin(const std::string& why) {
  const auto start = std::chrono::steady_clock::now();
  spdlog::warn("rejoining DDS domain {} with a new participant: {}", config_.domain, why);
  // Made before the old one leaves (a rejoin is not a leave): peers that meet the new participant
  // while the old one still announces this daemon never see it gone, so none of them takes its
  // scenes over (read as "left while holding" when the old one left first: CI, 2026-11-27).
  std::unique_ptr<DdsEndpoints> old;
  try {
    auto fresh = std::make_unique<DdsEndpoints>(*this, config_, joined_ms_);
    std::unique_lock lock(dds_mutex_);
    old = std::move(dds_);
    dds_ = std::move(fresh);
  } catch (const std::exception& e) {
    spdlog::error("rejoining DDS domain {} failed: {}; the old participant stays, trying again in {:.0f} s",
                  config_.domain, e.what(), std::chrono::duration<double>(rejoin_schedule_.period()).count());
    return;
  }
  std::vector<std::string> heard;  // the daemons the old participant heard, which must hear the new one
  if (old) {
    old->stop_requests();  // requests are answered by the new participant alone
    for (const msg::DaemonInfo& d : old->other_daemons()) heard.push_back(d.server_id().to_string());
  }
  announce();
  for (const std::string& scene : service_->loaded_scenes()) {
    try {
      const auto session = service_->session(scene);
      publish_status(*session);
      mark_version(scene, *session);
    } catch (const std::exception&) {
      // unloaded meanwhile
    }
  }
  const bool all_heard = overlap_until_heard(heard);
  old.reset();  // peers see the old participant leave, and keep the new one's announcement
  announce();   // the latest announcement everywhere is the new participant's
  spdlog::info("rejoined DDS domain {} in {:.2f} s; {} other daemons heard{}", config_.domain,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), other_daemons().size(),
               all_heard ? "" : " (not every daemon the old participant heard)");
}

bool Daemon::overlap_until_heard(const std::vector<std::string>& heard) {
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
  std::unique_lock lock(fleet_mutex_);
  while (!fleet_stop_) {
    const auto elapsed = std::chrono::steady_clock::now() - start;
    if (elapsed >= kRejoinOverlap) break;
    if (elapsed >= listen) {
      lock.unlock();
      const bool done = all_heard();
      lock.lock();
      if (done) return true;
    }
    fleet_wake_.wait_for(lock, std::chrono::milliseconds(100), [this] { return fleet_stop_; });
  }
  return all_heard();
}

}  // namespace ispars::server
