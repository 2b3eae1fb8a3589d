#include "ispars/wire/rejoin_schedule.hpp"

#include <fmt/format.h>

namespace ispars::wire {
namespace {

constexpr std::size_t kMaxFirstTried = 1024;

}  // namespace

std::string RejoinSchedule::reason(const PeerWatch::Peer& peer) const {
  return fmt::format("{} ({}) {} within {:.0f} s", peer.name, peer.prefix,
                     peer.first_meeting ? "was discovered and did not authenticate"
                                        : "came back after its lease ran out here and did not authenticate again",
                     std::chrono::duration<double>(grace_).count());
}

RejoinSchedule::Decision RejoinSchedule::poll(PeerWatch& peers, Clock::time_point now) {
  Decision decision;
  if (last_ && now - *last_ < period_) {
    if (auto peer = peers.unhealed(now, grace_); peer && peer->prefix != deferred_said_) {
      deferred_said_ = peer->prefix;
      decision.deferred = std::move(peer);
      decision.since_last = now - *last_;
    }
    return decision;
  }
  if (retry_) {
    decision.now = std::exchange(retry_, std::nullopt);
  } else {
    decision.now = peers.take_unhealed(now, grace_);
    while (decision.now && decision.now->first_meeting && first_tried_.contains(decision.now->prefix)) {
      decision.given_up = std::exchange(decision.now, peers.take_unhealed(now, grace_));
    }
    if (decision.now && decision.now->first_meeting) {
      if (first_tried_.size() >= kMaxFirstTried) first_tried_.clear();
      first_tried_.insert(decision.now->prefix);
    }
  }
  if (decision.now) {
    last_ = now;
    deferred_said_.clear();
  }
  return decision;
}

}  // namespace ispars::wire
