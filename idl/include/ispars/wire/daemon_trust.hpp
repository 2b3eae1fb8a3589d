#pragma once
// Whose statuses and updates to believe: a SceneStatus or UpdateBatch that names daemon S counts
// only when its writer belongs to a participant that announces S on ispars/daemons and has not
// left (transport identity, never a field). One rule for clients, replicas and daemons. While a
// daemon rejoins, its old and new participants both announce it: the samples of either count,
// whichever announcement arrived last (a status of the new one refused then, and replaced before
// the next announcement by a later status, was lost to every takeover).

#include <string>

#include "ispars.h"
#include "ispars/wire/latest_samples.hpp"

namespace ispars::wire {

/// Whether `sender` (wire::identity_of of a sample's writer) announces daemon `server_id`.
[[nodiscard]] inline bool written_by_daemon(const LatestSamples<msg::DaemonInfo>& daemons, const std::string& server_id,
                                            const std::string& sender) {
  return !sender.empty() && daemons.written_by(server_id, sender);
}

/// The accept rule of a LatestSamples of a message naming its daemon (`server_id`, a status or a
/// task): only from the daemon it names. `daemons` must outlive the rule.
template <class Message>
[[nodiscard]] typename LatestSamples<Message>::Accept from_their_daemon(const LatestSamples<msg::DaemonInfo>& daemons) {
  return [&daemons](const Message& m, const std::string& sender) {
    return written_by_daemon(daemons, m.server_id().to_string(), sender);
  };
}

/// from_their_daemon for statuses.
[[nodiscard]] inline LatestSamples<msg::SceneStatus>::Accept statuses_from_their_daemon(
    const LatestSamples<msg::DaemonInfo>& daemons) {
  return from_their_daemon<msg::SceneStatus>(daemons);
}

}  // namespace ispars::wire
