#pragma once
// When a long-lived participant (isparsd, a secured client) replaces itself: a peer that came
// back after it was dropped here and has not authenticated again within a grace (PeerWatch:
// "unhealed") makes a rejoin due, at most once per period. A peer that authenticates within the
// grace (both sides had dropped each other), leaves (it stopped, or rejoined itself) or is dropped
// again makes none. Not thread-safe: one thread (the daemon's fleet thread, a client's watch)
// owns it.

#include <chrono>
#include <optional>
#include <string>

#include "ispars/wire/participant.hpp"

namespace ispars::wire {

/// See the file comment.
class RejoinSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  RejoinSchedule(Clock::duration period, Clock::duration grace) : period_(period), grace_(grace) {}

  /// What poll() decided.
  struct Decision {
    std::optional<PeerWatch::Peer> now;       ///< Rejoin now, for this peer.
    std::optional<PeerWatch::Peer> deferred;  ///< Unhealed within the period of the last rejoin (said once).
    Clock::duration since_last{};             ///< With `deferred`: how long ago the last rejoin was.
  };
  /// Looks at `peers` at `now` and decides.
  [[nodiscard]] Decision poll(PeerWatch& peers, Clock::time_point now);
  /// A rejoin poll() asked for failed: it is due again one period after the attempt.
  void failed(const PeerWatch::Peer& peer) { retry_ = peer; }
  [[nodiscard]] Clock::duration period() const { return period_; }
  [[nodiscard]] Clock::duration grace() const { return grace_; }

 private:
  Clock::duration period_;
  Clock::duration grace_;
  std::optional<Clock::time_point> last_;
  std::optional<PeerWatch::Peer> retry_;
  std::string deferred_said_;  // the prefix whose deferral was last reported
};

}  // namespace ispars::wire
