#pragma once
// A build request (roadmap/build_request.hpp) as the wire carries it, msg::BuildArgs: method and
// variant by name, and each override a typed member with its bit in a presence mask.

#include <string_view>

#include "ispars.h"
#include "ispars/roadmap/build_request.hpp"

namespace ispars::wire {

/// `request` as a BuildArgs message (its generation stays behind: a client never sets one).
[[nodiscard]] msg::BuildArgs to_message(const BuildRequest& request);

/// The request `args` carries. Throws InputError (file `file`) naming "method" or "variant" for
/// an unknown name, or "overrides" for a presence bit this version does not know. Ranges are
/// make_recipe's to check.
[[nodiscard]] BuildRequest from_message(const msg::BuildArgs& args, std::string_view file);

}  // namespace ispars::wire
