// A session's build job (roadmap_session_job.cpp): what readers are served when a job ends.

#include <gtest/gtest.h>

#include <atomic>
#include <memory>

#include "ispars/service/roadmap_session.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

// A cancel that lands just after a commit whose chunk took no copy for readers (the copy is
// decided before the cancel, and only every quarter second or so) ends the loop there: readers
// must still get that last commit, as the status's samples say. CI's kill -9 campaign saw a
// snapshot one chunk older than the status after such a cancel.
TEST(RoadmapSessionJob, ACancelRightAfterACommitLeavesReadersThatCommitNotAnOlderOne) {
  const Scene& scene = test::shared_scene("demo_tank_tower");
  for (const BuildMethod method : {BuildMethod::ispars, BuildMethod::dense, BuildMethod::ispars2}) {
    SCOPED_TRACE(std::string(to_string(method)));
    test::TempDir dir;
    std::unique_ptr<RoadmapSession> session;
    int commits = 0;
    SessionCallbacks callbacks;
    callbacks.on_commit = [&](const RoadmapBatch&, std::uint64_t, std::uint64_t) {
      if (++commits == 3) {
        EXPECT_TRUE(session->cancel());  // after the first chunk's copy, within a second
      }
    };
    session = std::make_unique<RoadmapSession>("tower", scene, dir.path() / "tower", SessionLimits{}, callbacks);
    BuildRequest request;
    request.method = method;
    request.samples = 100'000;
    request.seed = 4;
    session->request_build(request);
    std::atomic<bool> never{false};
    session->run_job(never);
    const SessionStatus status = session->status();
    ASSERT_EQ(status.state, SessionState::idle);
    ASSERT_EQ(commits, 3);
    ASSERT_LT(status.samples_done, 100'000u);
    const PublishedRoadmap published = session->published();
    EXPECT_EQ(published.samples, status.samples_done);
    BuildOptions options;
    options.seed = 4;
    auto reference = make_roadmap_builder(method, scene, options);
    reference->extend(status.samples_done);
    EXPECT_EQ(roadmap_digest(*published.roadmap), roadmap_digest(reference->roadmap()))
        << "readers were served an older roadmap than the status's " << status.samples_done << " samples";
  }
}

}  // namespace
}  // namespace ispars
