// SceneFingerprints and the listing that uses it: a stored copy is offered to the fleet only while
// this daemon's scene file is the one it was built on.

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "ispars/service/roadmap_service.hpp"
#include "ispars/service/scene_fingerprints.hpp"
#include "server/service_waits.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

class SceneFingerprintsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_.path() / "scenes");
    write_scene(1);
  }
  void write_scene(int seed) const {
    std::ofstream(dir_.path() / "scenes" / "s0.yaml") << "procedural: {kind: tank_tower, seed: " << seed << "}\n";
  }
  // A roadmap of s0 built and stored by a service that then stops.
  void store_s0() const {
    ServiceSettings s;
    s.server_id = "unit";
    s.scene_dir = dir_.path() / "scenes";
    s.data_dir = dir_.path() / "data";
    s.build_workers = 1;
    RoadmapService service(s, {});
    (void)service.load("s0");
    BuildRequest r;
    r.samples = 300;
    service.build("s0", r);
    ASSERT_EQ(test::wait_idle(service, "s0").samples_done, 300u);
  }
  test::TempDir dir_;
};

TEST_F(SceneFingerprintsTest, AFingerprintFollowsTheSceneFile) {
  SceneFingerprints fingerprints(dir_.path() / "scenes");
  const CurrentFingerprint first = fingerprints.of("s0");
  ASSERT_EQ(first.problem, "");
  ASSERT_EQ(first.fingerprint.size(), 16u);
  EXPECT_EQ(fingerprints.of("s0").fingerprint, first.fingerprint);
  write_scene(2);
  std::filesystem::last_write_time(dir_.path() / "scenes" / "s0.yaml",
                                   std::filesystem::last_write_time(dir_.path() / "scenes" / "s0.yaml") +
                                       std::chrono::seconds(5));  // a new stamp even within one clock tick
  EXPECT_NE(fingerprints.of("s0").fingerprint, first.fingerprint) << "the edited file is fingerprinted again";
  EXPECT_NE(fingerprints.of("gone").problem.find("does not load"), std::string::npos);
}

TEST_F(SceneFingerprintsTest, AStoredCopyOfAnotherSceneFileVersionIsNotOffered) {
  store_s0();
  SceneFingerprints fingerprints(dir_.path() / "scenes");
  const auto data = dir_.path() / "data";
  StoredListing same = list_stored_roadmaps(data, {}, &fingerprints);
  ASSERT_EQ(same.served.size(), 1u);
  EXPECT_EQ(same.served[0].samples, 300u);
  EXPECT_TRUE(same.unservable.empty());

  write_scene(2);  // the user edits the scene file: the copy describes another structure
  std::filesystem::last_write_time(
      dir_.path() / "scenes" / "s0.yaml",
      std::filesystem::last_write_time(dir_.path() / "scenes" / "s0.yaml") + std::chrono::seconds(5));
  StoredListing edited = list_stored_roadmaps(data, {}, &fingerprints);
  EXPECT_TRUE(edited.served.empty()) << "a copy this daemon cannot serve outweighed healthy holders";
  ASSERT_EQ(edited.unservable.size(), 1u);
  EXPECT_NE(edited.unservable[0].why.find("another version of the scene file"), std::string::npos)
      << edited.unservable[0].why;
  EXPECT_EQ(edited.scenes, std::vector<std::string>{"s0"}) << "still listed as stored: nothing is removed";

  std::filesystem::remove(dir_.path() / "scenes" / "s0.yaml");
  StoredListing removed = list_stored_roadmaps(data, {}, &fingerprints);
  EXPECT_TRUE(removed.served.empty());
  ASSERT_EQ(removed.unservable.size(), 1u);
  EXPECT_NE(removed.unservable[0].why.find("does not load"), std::string::npos) << removed.unservable[0].why;

  write_scene(1);  // restored: offered again
  EXPECT_EQ(list_stored_roadmaps(data, {}, &fingerprints).served.size(), 1u);
}

}  // namespace
}  // namespace ispars::service
