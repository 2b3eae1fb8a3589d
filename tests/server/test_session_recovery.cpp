// A scene's stored roadmap taken over at load (recover_session), without a session around it: no
// store, a drop's generation kept, a roadmap with its task's POIs seen, and the stores refused
// (damaged, of another version of the scene) or not this scene's, with their files untouched.

#include "ispars/service/session_recovery.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "ispars/planning/scene/scene_fingerprint.hpp"
#include "roadmap_session_fixture.hpp"

namespace ispars::service {
namespace {

class SessionRecoveryTest : public RoadmapSessionTest {
 protected:
  RecoveredSession recover(const planning::Scene& scene, const std::string& name = "tower") {
    return recover_session(name, scene, scene_fingerprint(scene), dir_.path() / "tower", SessionLimits{}, disk());
  }
  // A stored roadmap of `samples` (and the task `task_pois` POIs, when not 0), made by a session.
  std::uint64_t store(std::uint64_t samples, std::size_t task_pois = 0) {
    auto session = open();
    session->request_build(ispars(samples, 3));
    session->run_job(never_);
    if (task_pois > 0) {
      session->request_task({"welds", sample_task_pois(scene(), task_pois, 4)});
      session->run_job(never_);
    }
    EXPECT_EQ(session->status().state, SessionState::idle) << session->status().last_error;
    return roadmap_digest(*session->published().roadmap);
  }
  static std::string bytes_of(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
};

TEST_F(SessionRecoveryTest, NoStoreRecoversNothingAndADropsGenerationIsKept) {
  RecoveredSession none = recover(scene());
  EXPECT_FALSE(none.stored);
  EXPECT_TRUE(none.refused.empty());
  EXPECT_FALSE(none.store);
  EXPECT_FALSE(none.dropped_generation);
  store(600);
  std::uint64_t dropped = 0;
  {
    auto session = open();
    session->drop();
    dropped = session->published().generation;
  }
  ASSERT_NE(dropped, 0u);
  RecoveredSession after = recover(scene());
  EXPECT_FALSE(after.stored);
  EXPECT_EQ(after.dropped_generation, dropped);
}

TEST_F(SessionRecoveryTest, AStoredRoadmapIsRecoveredWithItsTasksPoisSeen) {
  const std::uint64_t digest = store(1500, 30);
  RecoveredSession r = recover(scene());
  ASSERT_TRUE(r.stored);
  EXPECT_TRUE(r.refused.empty());
  ASSERT_TRUE(r.store);
  const StoredRoadmap& s = *r.stored;
  EXPECT_EQ(s.recipe.method, BuildMethod::ispars);
  EXPECT_EQ(s.published.samples, 1500u);
  EXPECT_EQ(s.published.generation, s.recipe.generation);
  EXPECT_EQ(roadmap_digest(*s.published.roadmap), digest) << "the recovered roadmap is not the one stored";
  ASSERT_EQ(s.tasks.size(), 1u);
  EXPECT_EQ(s.tasks[0].name, "welds");
  EXPECT_EQ(s.scene_with_tasks->pois().size(), scene().pois().size() + 30);
  EXPECT_EQ(s.published.roadmap->poi_count(), scene().pois().size() + 30);
  EXPECT_EQ(r.resume_from.has_value(), !planning::resumes_from_roadmap(BuildMethod::ispars));
  EXPECT_NE(r.note.find("recovered ispars roadmap at version"), std::string::npos) << r.note;
  EXPECT_NE(r.note.find("1 tasks"), std::string::npos) << r.note;
  EXPECT_TRUE(r.torn_tail_note.empty()) << r.torn_tail_note;
}

TEST_F(SessionRecoveryTest, ADamagedStoreIsRefusedAndLeftAsItIs) {
  store(800);
  const auto snapshot = dir_.path() / "tower" / "snapshot.bin";
  write_file_atomically(snapshot, "ISPSNP01 damaged");
  const std::string journal = bytes_of(dir_.path() / "tower" / "journal.log");
  RecoveredSession r = recover(scene());
  EXPECT_NE(r.refused.find("snapshot.bin is damaged"), std::string::npos) << r.refused;
  EXPECT_FALSE(r.store);
  EXPECT_FALSE(r.stored);
  EXPECT_EQ(bytes_of(snapshot), "ISPSNP01 damaged");
  EXPECT_EQ(bytes_of(dir_.path() / "tower" / "journal.log"), journal);
}

TEST_F(SessionRecoveryTest, AStoreOfAnotherVersionOfTheSceneIsRefusedAndReleased) {
  const std::uint64_t digest = store(800);
  const scene_files::SceneConfig& c = scene().config();
  const planning::Scene edited =
      scene().with_roadmap_parameters(c.dense_delta * 0.9, c.sparse_delta, c.stretch, "edited");
  RecoveredSession refused = recover(edited);
  EXPECT_NE(refused.refused.find("was built on another version of the scene"), std::string::npos) << refused.refused;
  EXPECT_FALSE(refused.store) << "a refused store stays open (and locked)";
  EXPECT_FALSE(refused.stored);
  // Untouched, and released: the scene as it was recovers it at once.
  RecoveredSession again = recover(scene());
  ASSERT_TRUE(again.stored) << again.refused;
  EXPECT_EQ(roadmap_digest(*again.stored->published.roadmap), digest);
}

TEST_F(SessionRecoveryTest, AnotherScenesStoreIsAnError) {
  store(600);
  try {
    (void)recover(scene(), "silo");
    FAIL() << "another scene's store was recovered";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("belongs to scene 'tower', not 'silo'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ispars::service
