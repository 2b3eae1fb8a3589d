#pragma once
// A session's status as the SceneStatus message the daemon publishes (the service's own type
// on the wire; clients read the message itself).

#include <cstdint>
#include <optional>
#include <string>

#include "ispars.h"
#include "ispars/service/roadmap_session.hpp"

namespace ispars::server {

/// `status` as a status message from `server_id`, for the roadmap of `generation`.
[[nodiscard]] msg::SceneStatus to_message(const service::SessionStatus& status, const std::string& server_id,
                                          std::uint64_t generation);
/// The recipe a status message carries (to_message's inverse for those fields); nullopt when it
/// names no method, or a method or variant this daemon does not know.
[[nodiscard]] std::optional<RoadmapRecipe> recipe_of(const msg::SceneStatus& status);
/// The wire's name for a session state.
[[nodiscard]] msg::SceneState to_message(service::SessionState state);

}  // namespace ispars::server
