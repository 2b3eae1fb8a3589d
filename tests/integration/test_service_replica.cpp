// Replicas and the update history: a drop or an unload reaches every replica and releases the
// batches the daemon keeps for late joiners; the CLI's watch says so and writes no stale file; a
// replica of one scene receives no other scene's batches.

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iterator>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "support/raw_peer.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;

using namespace std::chrono_literals;

class ReplicaTest : public ServiceTest {
 protected:
  // Loads and builds `scene`, and waits until `replica` holds the built roadmap.
  SceneStatus build_followed(Client& client, client::RoadmapReplica& replica, const std::string& scene) {
    client.build(scene, ispars_build(1500));
    const SceneStatus built = client.wait_idle(scene, {}, kLong);
    EXPECT_TRUE(replica.wait_for(built.generation, built.version, std::chrono::seconds(30)));
    EXPECT_GT(replica.roadmap().vertex_count(), 0u);
    return built;
  }
};

TEST_F(ReplicaTest, ADropEmptiesEveryReplicaAndReleasesTheKeptBatches) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.load("s1");
  client::RoadmapReplica replica(client, "s0");
  client::RoadmapReplica other(client, "s1");
  build_followed(client, replica, "s0");
  build_followed(client, other, "s1");
  RawPeer late(domain_);
  ASSERT_GT(late.kept_update_batches("s0", std::chrono::milliseconds(1500)), 0u);  // kept for late joiners
  client.drop("s0");
  ASSERT_TRUE(eventually([&] { return replica.retirements() == 1; }, 20s, "the replica retires its roadmap"));
  EXPECT_EQ(replica.roadmap().vertex_count(), 0u);
  EXPECT_EQ(other.retirements(), 0u);  // another scene's replica is untouched
  EXPECT_GT(other.roadmap().vertex_count(), 0u);
  RawPeer later(domain_);
  EXPECT_EQ(later.kept_update_batches("s0", std::chrono::milliseconds(1500)), 0u);
  EXPECT_GT(later.kept_update_batches("s1", std::chrono::milliseconds(1500)), 0u);
  // A new build on the same scene is followed again by the same replica.
  const SceneStatus rebuilt = build_followed(client, replica, "s0");
  EXPECT_EQ(replica.generation(), rebuilt.generation);
  // The positive control of `other`'s zero retirements above: a drop of s1 does reach s1's
  // replica, so that zero was not the count of a replica deaf to every drop.
  client.drop("s1");
  EXPECT_TRUE(eventually([&] { return other.retirements() >= 1; }, 20s, "s1's replica retires"))
      << "a drop of s1 never reached s1's replica";
  EXPECT_EQ(other.roadmap().vertex_count(), 0u);
}

// A replica of s0 subscribes through a filter on its scene: while s1 is built and followed by no
// one, none of s1's batches reaches it (an unfiltered late joiner still gets them), and it keeps
// following s0.
TEST_F(ReplicaTest, AReplicaOfOneSceneReceivesNoOtherScenesBatches) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.load("s1");
  client::RoadmapReplica replica(client, "s0");
  client.build("s1", ispars_build(3000));
  const SceneStatus s1 = client.wait_idle("s1", {}, kLong);
  ASSERT_GT(s1.version, 0u);
  const SceneStatus s0 = build_followed(client, replica, "s0");
  EXPECT_EQ(replica.generation(), s0.generation);
  EXPECT_EQ(replica.batches_of_other_scenes(), 0u);
  RawPeer unfiltered(domain_);
  EXPECT_GT(unfiltered.kept_update_batches("s1", std::chrono::milliseconds(1500)), 0u);
}

// A replica whose owner's callback stalls while an extend streams batches: its queue (bounded at
// two batches here) drops the oldest, the gap is detected when the callback returns, and the
// replica resyncs from a snapshot to exactly the daemon's roadmap.
TEST_F(ReplicaTest, AReplicaThatFallsBehindDropsItsOldestBatchesAndResyncsToTheSameRoadmap) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  std::mutex mutex;
  std::condition_variable released_cv;
  bool stall = false;
  bool released = false;
  bool stalled = false;
  client::RoadmapReplica replica(
      client, "s0",
      [&](const client::ReplicaEvent& event) {
        std::unique_lock lock(mutex);
        if (!stall || event.resynced || released) return;
        stalled = true;
        released_cv.notify_all();
        released_cv.wait(lock, [&] { return released; });
      },
      client::ReplicaLimits{2, 64u << 10});
  build_followed(client, replica, "s0");
  const std::size_t snapshots = replica.snapshots_taken();
  {
    std::lock_guard lock(mutex);
    stall = true;
  }
  client.extend("s0", 12000);
  {
    std::unique_lock lock(mutex);
    ASSERT_TRUE(released_cv.wait_for(lock, std::chrono::seconds(30), [&] { return stalled; }))
        << "the replica applied no batch of the extend";
  }
  const SceneStatus extended = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(extended.state, SceneState::idle) << extended.last_error;
  EXPECT_GT(replica.batches_dropped(), 0u) << "the extend sent too few batches to fill the queue";
  {
    std::lock_guard lock(mutex);
    released = true;
  }
  released_cv.notify_all();
  ASSERT_TRUE(replica.wait_for(extended.generation, extended.version, std::chrono::seconds(30)))
      << replica.last_error();
  EXPECT_GT(replica.snapshots_taken(), snapshots) << "the dropped batches did not lead to a resync";
  EXPECT_GT(replica.resyncs().gap, 0u) << "the resync was not counted as a gap's";
  const client::Snapshot snapshot = client.snapshot("s0");
  EXPECT_EQ(snapshot.version, extended.version);
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(snapshot.roadmap));
  EXPECT_THROW(client::RoadmapReplica(client, "s0", {}, client::ReplicaLimits{0, 64u << 10}), std::invalid_argument);
  EXPECT_THROW(client::RoadmapReplica(client, "s0", {}, client::ReplicaLimits{2, 1000}), std::invalid_argument);
  EXPECT_THROW(
      client::RoadmapReplica(client, "s0", {}, client::ReplicaLimits{2, 64u << 10, std::chrono::milliseconds(99)}),
      std::invalid_argument);
}

TEST_F(ReplicaTest, AnUnloadEmptiesTheReplicaAndALoadBringsItBack) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s2");
  client::RoadmapReplica replica(client, "s2");
  const SceneStatus built = build_followed(client, replica, "s2");
  const std::uint64_t digest = roadmap_digest(replica.roadmap());
  client.unload("s2");
  ASSERT_TRUE(eventually([&] { return replica.retirements() == 1; }, 20s, "the replica retires its roadmap"));
  EXPECT_EQ(replica.roadmap().vertex_count(), 0u);
  // Not checked here: the kept batches of an unload right after a build are not reliably
  // released (Fast DDS 2.9 keeps some batches through the unregister when they were just
  // written; seen under load). The drop test checks release after batches have settled.
  client.load("s2");  // its stored roadmap comes back, and so does the replica
  ASSERT_TRUE(eventually([&] { return replica.roadmap().vertex_count() > 0; }, 30s, "the replica holds a roadmap"));
  EXPECT_EQ(roadmap_digest(replica.roadmap()), digest);
  EXPECT_EQ(replica.version(), built.version);
}

TEST_F(ReplicaTest, WatchStopsOnADropAndWritesNoStaleFile) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s3");
  client.build("s3", ispars_build(1500));
  client.wait_idle("s3", {}, kLong);
  const auto dump = dir_.path() / "replica.json";
  const auto out_file = dir_.path() / "watch.out";
  // Bounded: a watch that never sees the drop fails the test instead of hanging it.
  const std::string command = "timeout 60 " + std::string(ISPARS_CLI) + " --domain " + std::to_string(domain_) +
                              " watch s3 --dump " + dump.string() + " > " + out_file.string() + " 2>&1";
  int status = -1;
  std::thread watcher([&] { status = std::system(command.c_str()); });
  // The watch shows progress once it follows the scene; then give its replica a moment to sync.
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(out_file) && std::filesystem::file_size(out_file) > 0; },
                         20s, "the watch shows progress"));
  std::this_thread::sleep_for(std::chrono::seconds(2));
  client.drop("s3");
  watcher.join();
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_FALSE(std::filesystem::exists(dump));
  std::ifstream in(out_file);
  const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(out.find("the roadmap of scene 's3' was dropped while watching; nothing written to"), std::string::npos)
      << out;
}

}  // namespace
}  // namespace ispars::test
