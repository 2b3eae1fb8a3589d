#pragma once
// When a long-lived participant (isparsd, a secured client) replaces itself: a peer whose session
// is missing for a grace (PeerWatch: "unhealed": it came back after it was dropped here, or it is
// a daemon whose first handshake never ended) makes a rejoin due, at most once per period. A peer
// that authenticates within the grace (both sides had dropped each other), leaves (it stopped, or
// rejoined itself) or is dropped again makes none. A first meeting makes one rejoin per peer: if
// the new participant cannot meet it either, the peer is given up (a participant that cannot
// authenticate, such as a daemon without security, would otherwise make one every period). Not
// thread-safe: one thread (the daemon's fleet thread, a client's watch) owns it.

#include <chrono>
#include <optional>
#include <set>
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
    std::optional<PeerWatch::Peer> given_up;  ///< A first meeting that failed again after a rejoin.
  };
  /// Looks at `peers` at `now` and decides.
  [[nodiscard]] Decision poll(PeerWatch& peers, Clock::time_point now);
  /// A rejoin poll() asked for failed: it is due again one period after the attempt.
  void failed(const PeerWatch::Peer& peer) { retry_ = peer; }
  [[nodiscard]] Clock::duration period() const { return period_; }
  [[nodiscard]] Clock::duration grace() const { return grace_; }
  /// Why `peer` makes a rejoin due, for the log: "isparsd b (01.0f...) came back after ...".
  [[nodiscard]] std::string reason(const PeerWatch::Peer& peer) const;

 private:
  Clock::duration period_;
  Clock::duration grace_;
  std::optional<Clock::time_point> last_;
  std::optional<PeerWatch::Peer> retry_;
  std::string deferred_said_;          // the prefix whose deferral was last reported
  std::set<std::string> first_tried_;  // first meetings a rejoin was made for (bounded)
};

}  // namespace ispars::wire
