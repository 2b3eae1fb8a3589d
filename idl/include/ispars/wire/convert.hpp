#pragma once
// Conversions between the roadmap types a client needs and the IDL messages.

#include <string>

#include "ispars.h"
#include "ispars/roadmap/roadmap_batch.hpp"

namespace ispars::wire {

[[nodiscard]] msg::Point to_message(const Vec3& p);
[[nodiscard]] Vec3 from_message(const msg::Point& p);

/// A roadmap batch as an update message.
[[nodiscard]] msg::UpdateBatch to_message(const RoadmapBatch& batch, const std::string& scene,
                                          const std::string& server_id, std::uint64_t generation,
                                          std::uint64_t samples_done);
/// An update message as a roadmap batch. Throws std::runtime_error when the message is not
/// self-consistent (order and contents disagree, ids out of sequence).
[[nodiscard]] RoadmapBatch from_message(const msg::UpdateBatch& message);

[[nodiscard]] std::string to_string(msg::SceneState state);
/// The operation's short name ("list", "load", ..., "tour"); "unknown" for a value outside the enum.
[[nodiscard]] std::string to_string(msg::Operation operation);

/// A reply body whose discriminator is `operation`, with that operation's member defaulted (a
/// union's discriminator can only be set together with its member).
[[nodiscard]] msg::ReplyBody empty_reply_body(msg::Operation operation);
/// The same for requests: query and change arguments for `operation`, defaulted. Throws
/// std::invalid_argument when `operation` is not a query (resp. a change).
[[nodiscard]] msg::QueryArgs query_args(msg::Operation operation);
[[nodiscard]] msg::ChangeArgs change_args(msg::Operation operation);

}  // namespace ispars::wire
