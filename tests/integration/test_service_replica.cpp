// Replicas and the update history: a drop or an unload reaches every replica and releases the
// batches the daemon keeps for late joiners; the CLI's watch says so and writes no stale file.

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "support/raw_peer.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;

template <class Predicate>
bool eventually(Predicate ready, std::chrono::seconds timeout = std::chrono::seconds(20)) {
  const auto deadline = Clock::now() + timeout;
  while (Clock::now() < deadline) {
    if (ready()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return ready();
}

class ReplicaTest : public ServiceTest {
 protected:
  // Loads and builds `scene`, and waits until `replica` holds the built roadmap.
  msg::SceneStatus build_followed(Client& client, client::RoadmapReplica& replica, const std::string& scene) {
    client.build(scene, ispars_build(1500));
    const msg::SceneStatus built = client.wait_idle(scene, {}, kLong);
    EXPECT_TRUE(replica.wait_for(built.generation(), built.version(), std::chrono::seconds(30)));
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
  ASSERT_TRUE(eventually([&] { return replica.retirements() == 1; }));
  EXPECT_EQ(replica.roadmap().vertex_count(), 0u);
  EXPECT_EQ(other.retirements(), 0u);  // another scene's replica is untouched
  EXPECT_GT(other.roadmap().vertex_count(), 0u);
  RawPeer later(domain_);
  EXPECT_EQ(later.kept_update_batches("s0", std::chrono::milliseconds(1500)), 0u);
  EXPECT_GT(later.kept_update_batches("s1", std::chrono::milliseconds(1500)), 0u);
  // A new build on the same scene is followed again by the same replica.
  const msg::SceneStatus rebuilt = build_followed(client, replica, "s0");
  EXPECT_EQ(replica.generation(), rebuilt.generation());
}

TEST_F(ReplicaTest, AnUnloadEmptiesTheReplicaAndALoadBringsItBack) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s2");
  client::RoadmapReplica replica(client, "s2");
  const msg::SceneStatus built = build_followed(client, replica, "s2");
  const std::uint64_t digest = roadmap_digest(replica.roadmap());
  client.unload("s2");
  ASSERT_TRUE(eventually([&] { return replica.retirements() == 1; }));
  EXPECT_EQ(replica.roadmap().vertex_count(), 0u);
  // Not checked here: the kept batches of an unload right after a build are not reliably
  // released (Fast DDS 2.9 keeps some batches through the unregister when they were just
  // written; seen under load). The drop test checks release after batches have settled.
  client.load("s2");  // its stored roadmap comes back, and so does the replica
  ASSERT_TRUE(eventually([&] { return replica.roadmap().vertex_count() > 0; }, std::chrono::seconds(30)));
  EXPECT_EQ(roadmap_digest(replica.roadmap()), digest);
  EXPECT_EQ(replica.version(), built.version());
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
  ASSERT_TRUE(eventually([&] { return std::filesystem::exists(out_file) && std::filesystem::file_size(out_file) > 0; }));
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
