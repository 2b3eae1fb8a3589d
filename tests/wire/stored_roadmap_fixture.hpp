#pragma once
// Announcements for the fleet rule's tests: a daemon's copy of a scene's roadmap.

#include <algorithm>
#include <cstdint>
#include <string>

#include "ispars.h"

namespace ispars::test {

/// `daemon` with a copy of "s" announced: its generation, samples committed and accepted
/// (target, at least the samples) and the daemon it was handed to.
inline msg::DaemonInfo& add_copy(msg::DaemonInfo& daemon, std::uint64_t generation, std::uint64_t samples,
                                 std::uint64_t target = 0, const std::string& yielded_to = "") {
  msg::StoredRoadmap r;
  r.scene("s");
  r.generation(generation);
  r.samples(samples);
  r.target(std::max(samples, target));
  r.yielded_to(yielded_to);
  daemon.roadmaps().push_back(r);
  return daemon;
}

}  // namespace ispars::test
