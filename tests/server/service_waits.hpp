#pragma once
// Waiting on a RoadmapService in its unit tests: until no job runs or waits on a scene.

#include <chrono>
#include <string>

#include "ispars/service/roadmap_service.hpp"
#include "support/eventually.hpp"

namespace ispars::test {

/// `scene`'s status once no job runs or waits on it (a failure of the test after a minute).
inline service::SessionStatus wait_idle(const service::RoadmapService& service, const std::string& scene) {
  service::SessionStatus s;
  EXPECT_TRUE(eventually(
      [&] {
        s = service.stats(scene);
        return s.state != service::SessionState::queued && s.state != service::SessionState::building &&
               s.state != service::SessionState::replaying;
      },
      std::chrono::seconds(60), scene + " has no job", std::chrono::milliseconds(5)));
  return s;
}

}  // namespace ispars::test
