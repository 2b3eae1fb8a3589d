// A session's drop: remembered after its store is gone (the fleet weighs the drop's empty
// roadmap), and refused whole when it cannot be remembered.

#include <gtest/gtest.h>

#include <fstream>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "roadmap_session_fixture.hpp"

namespace ispars {
namespace {

TEST_F(RoadmapSessionTest, ADropIsRememberedAcrossAReopenAndALaterBuildIsNewerStill) {
  std::uint64_t built = 0, dropped = 0;
  {
    auto session = open();
    session->request_build(ispars(500));
    session->run_job(never_);
    built = session->status().generation;
    ASSERT_GT(built, 0u);
    session->drop();
    const SessionStatus after = session->status();
    EXPECT_EQ(after.state, SessionState::empty);
    dropped = after.generation;
    EXPECT_GT(dropped, built);
    EXPECT_EQ(session->published().generation, dropped);
    session->close();
  }
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "tower")) << "the store outlived its drop";
  auto session = open();
  EXPECT_EQ(session->status().state, SessionState::empty);
  EXPECT_FALSE(session->status().recipe);
  EXPECT_EQ(session->status().generation, dropped) << "the reopened scene forgot its drop";
  EXPECT_EQ(session->published().generation, dropped);
  session->request_build(ispars(300));
  session->run_job(never_);
  EXPECT_GT(session->status().recipe->generation, dropped);
}

// The mark cannot be written (a file stands where its directory goes): the drop is refused
// naming the file, and the roadmap stays as it was, stored and served.
TEST_F(RoadmapSessionTest, ADropThatCannotBeRememberedIsRefusedAndChangesNothing) {
  auto session = open();
  session->request_build(ispars(500));
  session->run_job(never_);
  const SessionStatus before = session->status();
  const std::uint64_t digest = roadmap_digest(*session->published().roadmap);
  std::ofstream(dir_.path() / ".drops") << "in the way\n";
  try {
    session->drop();
    ADD_FAILURE() << "the drop was not refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find(".drops"), std::string::npos) << e.what();
  }
  const SessionStatus after = session->status();
  EXPECT_EQ(after.state, SessionState::idle);
  EXPECT_EQ(after.generation, before.generation);
  EXPECT_EQ(after.samples_done, before.samples_done);
  EXPECT_EQ(roadmap_digest(*session->published().roadmap), digest);
  session->request_extend(200);  // the store still takes commits
  session->run_job(never_);
  EXPECT_EQ(session->status().samples_done, before.samples_done + 200);
  session->close();
  auto reopened = open();
  EXPECT_EQ(reopened->status().samples_done, before.samples_done + 200);
  EXPECT_EQ(reopened->status().generation, before.generation);
}

}  // namespace
}  // namespace ispars
