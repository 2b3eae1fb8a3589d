// isparsd rejoining its DDS domain with a new participant, under DDS Security. A peer (daemon or
// client) this one dropped (its lease ran out here), then discovered again under the same GUID,
// and which has not authenticated again within a grace (wire::RejoinSchedule) kept running: it
// stalled or the link was cut one way. The sessions between the two may never recover: Debian's
// Fast DDS 2.9.1 cannot authenticate a peer again while the other side keeps its DDS Security
// session. A new participant (a new GUID) meets every peer afresh. The daemon keeps its scenes,
// claims and jobs; it announces itself and publishes each scene's status again, and its fleet
// thread listens a discovery wait before applying the fleet's rule (so it does not take the
// scenes of daemons it has not heard yet). Replicas see a new update writer and resync.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <utility>


#include "daemon.hpp"
#include "dds_endpoints.hpp"

namespace ispars::server {
namespace {

// How long after rejoining the fleet's rule waits (at least): under DDS Security a handshake
// takes a few hundred milliseconds per peer.
constexpr std::chrono::milliseconds kRejoinListen{3000};

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
  if (config_.security.empty()) return;
  wire::RejoinSchedule::Decision decision;
  with_dds([&](DdsEndpoints& d) { decision = rejoin_schedule_.poll(d.peers(), std::chrono::steady_clock::now()); });
  if (decision.deferred) {
    spdlog::warn("{} ({}) came back after its lease ran out here and did not authenticate again; rejoined {:.0f} s "
                 "ago, so again {:.0f} s after that unless it authenticates, leaves or rejoins itself meanwhile",
                 decision.deferred->name, decision.deferred->prefix,
                 std::chrono::duration<double>(decision.since_last).count(),
                 std::chrono::duration<double>(rejoin_schedule_.period()).count());
  }
  if (decision.now) {
    rejoin(fmt::format("{} ({}) came back after its lease ran out here and did not authenticate again within {:.0f} s",
                       decision.now->name, decision.now->prefix,
                       std::chrono::duration<double>(rejoin_schedule_.grace()).count()));
  }
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
  last_rejoin_ = start;
  spdlog::warn("rejoining DDS domain {} with a new participant: {}", config_.domain, why);
  std::unique_ptr<DdsEndpoints> old;
  {
    std::unique_lock lock(dds_mutex_);
    old = std::move(dds_);
  }
  old.reset();  // peers see it leave; its callbacks find no endpoints and drop what they carry
  try {
    auto fresh = std::make_unique<DdsEndpoints>(*this, config_, joined_ms_);
    std::unique_lock lock(dds_mutex_);
    dds_ = std::move(fresh);
  } catch (const std::exception& e) {
    spdlog::error("rejoining DDS domain {} failed: {}; trying again in {:.0f} s", config_.domain, e.what(),
                  std::chrono::duration<double>(rejoin_schedule_.period()).count());
    return;
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
  {
    // Interrupted by a stop (SIGTERM is honoured within half a second).
    std::unique_lock lock(fleet_mutex_);
    fleet_wake_.wait_for(lock, std::max(kRejoinListen, std::chrono::milliseconds(config_.discovery_wait_ms)),
                         [this] { return fleet_stop_; });
  }
  spdlog::info("rejoined DDS domain {} in {:.2f} s; {} other daemons heard", config_.domain,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
               other_daemons().size());
}

}  // namespace ispars::server
