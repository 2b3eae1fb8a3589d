#pragma once
// The client's seam with the wire: requests sent as the protocol's messages (ispars.idl), for the
// protocol's own tests and the round-trip benchmark, and the conversion of messages to the
// library's types. Programs that only use the service include client.hpp and never this.

#include <chrono>
#include <optional>
#include <string>

#include "ispars.h"
#include "ispars/client/client.hpp"

namespace ispars::client {

/// A query (list, stats, path, snapshot, verify, tour) or a change (load, unload, build, extend,
/// cancel, drop) on `scene` with defaulted arguments, for call() or call_raw(). Throws
/// std::invalid_argument when `operation` is of the other kind.
[[nodiscard]] msg::QueryRequest make_query(msg::Operation operation, const std::string& scene);
[[nodiscard]] msg::ChangeRequest make_change(msg::Operation operation, const std::string& scene);

/// Sends one request to the daemon that owns its scene (or to `server`), retrying with the same
/// sequence number until a reply or the timeout; follows the scene when its owner leaves (unless
/// `server` was named). Throws ClientError(rejected) when the reply is an error, with the daemon's
/// message, and ClientError(protocol) when the daemon speaks another protocol version.
msg::Reply call(Client& client, msg::QueryRequest request, const std::string& server = {});
msg::Reply call(Client& client, msg::ChangeRequest request, const std::string& server = {});
/// Like call(), with its own timeout.
msg::Reply call(Client& client, msg::QueryRequest request, const std::string& server,
                std::chrono::milliseconds timeout);
/// Like call() but returns error replies instead of throwing.
msg::Reply call_raw(Client& client, msg::QueryRequest request, const std::string& server = {});
msg::Reply call_raw(Client& client, msg::ChangeRequest request, const std::string& server = {});

/// The daemons' announcements as they arrived (waits up to the client's timeout for the first),
/// for the fleet rule's functions (ispars/wire/scene_owner.hpp).
[[nodiscard]] std::vector<msg::DaemonInfo> daemon_messages(Client& client);

/// The messages as the library's types.
[[nodiscard]] SceneState from_message(msg::SceneState state);
[[nodiscard]] SceneStatus from_message(const msg::SceneStatus& status);
[[nodiscard]] SceneEntry from_message(const msg::SceneEntry& entry);
[[nodiscard]] TaskEntry from_message(const msg::TaskEntry& task);
[[nodiscard]] DaemonInfo from_message(const msg::DaemonInfo& info);
[[nodiscard]] Reply to_reply(const msg::Reply& reply);
[[nodiscard]] PathReply to_path_reply(const msg::Reply& reply);
[[nodiscard]] VerifyReply to_verify_reply(const msg::Reply& reply);
[[nodiscard]] TourReply to_tour_reply(const msg::Reply& reply);

}  // namespace ispars::client
