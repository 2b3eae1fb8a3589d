// A secured client rejoining its DDS domain with a new participant. A peer this client's
// participant dropped (its lease ran out here), then discovered again under the same GUID, and
// which has not authenticated again within a grace kept running while this side forgot it: a
// one-way loss, or a stall. Debian's Fast DDS 2.9.1 cannot
// authenticate the two again while the peer keeps its DDS Security session, and a daemon that
// never lost this client has no reason to rejoin itself, so this client would stay deaf to it.
// A new participant (a new GUID) meets every peer afresh. What the client knows (daemons,
// statuses), its calls and its participant's users (replicas) move to the new participant. A daemon
// whose first handshake with this client never ended (a Fast DDS 2.9.1 fault) makes one rejoin too.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "client_impl.hpp"

namespace ispars::client {
namespace {

// How often the participant's returned peers are looked at.
constexpr std::chrono::milliseconds kWatchPeriod{250};

}  // namespace

void Client::Impl::start_rejoin_watch() {
  // Without DDS Security Fast DDS meets a returning peer by itself.
  if (options_.participant.security.empty()) return;
  watch_ = std::jthread([this](std::stop_token stop) { watch_for_returned_peers(stop); });
}

void Client::Impl::stop_rejoin_watch() {
  if (!watch_.joinable()) return;
  watch_.request_stop();
  watch_wake_.notify_all();
  watch_.join();
}

void Client::Impl::watch_for_returned_peers(std::stop_token stop) {
  for (;;) {
    {
      std::unique_lock lock(watch_mutex_);
      watch_wake_.wait_for(lock, stop, kWatchPeriod, [] { return false; });
    }
    if (stop.stop_requested()) return;
    wire::RejoinSchedule::Decision decision;
    {
      std::shared_lock link(link_mutex_);
      decision = rejoin_schedule_.poll(link_->participant().peers(), std::chrono::steady_clock::now());
    }
    if (decision.now && !rejoin(rejoin_schedule_.reason(*decision.now))) {
      rejoin_schedule_.failed(*decision.now);
    }
  }
}

bool Client::Impl::rejoin(const std::string& why) {
  const auto start = std::chrono::steady_clock::now();
  const std::string old_id = id();
  spdlog::warn("client {}: rejoining DDS domain {} with a new participant: {}", old_id, options_.participant.domain,
               why);
  std::unique_ptr<ClientLink> fresh;
  try {
    fresh = std::make_unique<ClientLink>(options_.participant, listeners());
  } catch (const std::exception& e) {
    spdlog::error("client {}: rejoining DDS domain {} failed: {}; trying again in {:.0f} s", old_id,
                  options_.participant.domain, e.what(),
                  std::chrono::duration<double>(rejoin_schedule_.period()).count());
    return false;
  }
  std::unique_ptr<ClientLink> old;
  {
    std::unique_lock link(link_mutex_);
    for (ParticipantUser* user : users_) user->detach(link_->participant());
    if (link_->has_progress_reader()) fresh->ensure_progress_reader();
    old = std::exchange(link_, std::move(fresh));
    ++epoch_of_link_;
    set_id(link_->id());
    for (ParticipantUser* user : users_) user->attach(link_->participant());
  }
  old.reset();  // its peers see it leave; replies still addressed to it are not taken
  spdlog::info("client {} rejoined DDS domain {} as {} in {:.2f} s", old_id, options_.participant.domain, id(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return true;
}

}  // namespace ispars::client
