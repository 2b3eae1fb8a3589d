#include "ispars/wire/rejoin_schedule.hpp"

namespace ispars::wire {

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
  }
  if (decision.now) {
    last_ = now;
    deferred_said_.clear();
  }
  return decision;
}

}  // namespace ispars::wire
