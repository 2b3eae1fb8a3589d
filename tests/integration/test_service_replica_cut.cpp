// A replica cut off from its daemon on a real network (tests/support/netns_lab.hpp) while the
// roadmap changes in a way only the POI count shows: a task whose POIs the roadmap already
// covers adds no vertex, so the one batch that says so (no change, more POIs) is all there is of
// it, and the daemon then restarts, so its kept batches are gone when the cut heals. The status
// the replica sees after the heal shows the replica's own version (nothing was added), yet other
// POIs: the replica must learn the task from that and resync to the owner's snapshot (the fleet's
// history check met this after a partition: CI, 2026-12-02).

#include <gtest/gtest.h>

#include <fstream>

#include "integration/netns_fleet.hpp"
#include "ispars/client/replica.hpp"

namespace ispars::test {
namespace {

class ReplicaCutTest : public NetnsFleetTest {};

TEST_F(ReplicaCutTest, AReplicaCutOffWhileATaskNeedingNoVertexIsAddedAndTheDaemonRestartsLearnsIt) {
  lab_ =
      std::make_unique<NetnsLab>(dir_.path() / "netns", std::vector<std::string>{"d1", "hc"}, std::chrono::seconds(3));
  lab_->enter("hc");
  auto daemon = start_on("d1");
  auto client = joined(1);
  const SceneStatus built = load_and_build(*client, "s0", ispars_build(800, 4));
  client::RoadmapReplica replica(*client, "s0");
  ASSERT_TRUE(replica.wait_for(built.generation, built.version, std::chrono::seconds(30))) << replica.last_error();

  // Copies of five of the scene's own POIs, which the roadmap sees already.
  const std::vector<Vec3> scene_pois = client->snapshot("s0").pois;
  ASSERT_GE(scene_pois.size(), 5u);
  const std::filesystem::path file = dir_.path() / "copies.txt";
  {
    std::ofstream out(file);
    for (std::size_t i = 0; i < 5; ++i)
      out << scene_pois[i].x() << ' ' << scene_pois[i].y() << ' ' << scene_pois[i].z() << '\n';
  }
  lab_->cut("hc");
  ASSERT_TRUE(eventually([&] { return client->daemons().empty(); }, std::chrono::seconds(20),
                         "the client drops the daemon it was cut from", std::chrono::milliseconds(100)));
  const nlohmann::json added = cli_on("d1", "task add s0 copies --file " + file.string() + " --wait");
  ASSERT_EQ(added.at("tasks"), 1) << added.dump();
  ASSERT_EQ(added.at("version"), built.version) << "copies of covered POIs need no vertex: " << added.dump();
  const std::size_t poi_count = added.at("poi_count");
  ASSERT_EQ(poi_count, built.poi_count + 5) << added.dump();
  // Stopped before the heal, and started again on its stored roadmap after it: the batches it
  // kept for late joiners went with the old process.
  ASSERT_EQ(daemon->terminate(), 0);
  lab_->heal("hc");
  daemon = start_on("d1");

  EXPECT_TRUE(eventually([&] { return replica.roadmap().poi_count() == poi_count; }, std::chrono::seconds(30),
                         "the replica learns of the task after the heal", std::chrono::milliseconds(100)))
      << "the replica holds " << replica.roadmap().poi_count() << " POIs at version " << replica.version()
      << "; the owner " << poi_count << " at version " << built.version;
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client->snapshot("s0").roadmap));
  EXPECT_EQ(replica.pois().size(), poi_count);
  EXPECT_EQ(daemon->terminate(), 0);
}

}  // namespace
}  // namespace ispars::test
