// Inspection tasks through the daemon with the client library: a replica following a task
// resyncs to the snapshot; kill -9 at moments across an addition leaves the roadmap before or
// after it, never between, and the restart finishes the accepted addition to the roadmap an
// uninterrupted one gives, byte for byte.

#include <gtest/gtest.h>

#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/scene_files/poi_sampling.hpp"

namespace ispars::test {
namespace {

// The roadmap `method` builds in-process from `samples` with the scene's `count` sampled task
// POIs added afterwards (what the daemon's `--sample count --seed seed` adds).
std::uint64_t task_reference(const std::filesystem::path& scene_file, BuildMethod method, std::uint64_t samples,
                             std::size_t count, std::uint64_t seed) {
  const planning::Scene scene = planning::Scene::load(scene_file);
  const planning::Scene widened = scene.with_more_pois(
      scene_files::sample_pois_on_surface(scene.mesh(), count, seed, scene.config().pois.skip_ground));
  planning::BuildOptions options;
  options.seed = 1;
  const auto builder = planning::make_roadmap_builder(method, scene, options);
  builder->extend(samples);
  builder->add_pois(widened);
  return roadmap_digest(builder->roadmap());
}

BuildArgs build_of(const std::string& method, std::uint64_t samples) { return request_of(method, samples); }

TEST_F(ServiceTest, AReplicaFollowingATaskResyncsToTheSnapshot) {
  auto daemon = start("d");
  Client client(client_options(domain_));
  client.load("s0");
  client.build("s0", build_of("ispars2", 6000));
  const SceneStatus built = client.wait_idle("s0", {}, kLong);
  client::RoadmapReplica replica(client, "s0");
  ASSERT_TRUE(replica.wait_for(built.generation, built.version, std::chrono::seconds(20)));
  const std::size_t snapshots = replica.snapshots_taken();
  client.add_sampled_task("s0", "cracks", 50, 8);
  const SceneStatus added = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(added.tasks, 1u) << added.last_error;
  EXPECT_TRUE(eventually([&] { return replica.roadmap().poi_count() == added.poi_count; }, std::chrono::seconds(20),
                         "the replica learns of the task"));
  EXPECT_GT(replica.snapshots_taken(), snapshots) << "a task's POIs come with a snapshot";
  EXPECT_EQ(replica.pois().size(), added.poi_count);
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client.snapshot("s0").roadmap));
  EXPECT_EQ(roadmap_digest(replica.roadmap()),
            task_reference(scene_dir_ / "s0.yaml", BuildMethod::ispars2, 6000, 50, 8));
  const auto tasks = client.tasks("s0");
  ASSERT_EQ(tasks.size(), 1u);
  EXPECT_EQ(tasks[0].first_poi + tasks[0].poi_count, added.poi_count);

  // A task of POIs the roadmap already covers (copies of the scene's own) adds no guard: no new
  // version, no new vertex in the update stream; only the POI count tells the replica.
  const std::vector<Vec3> scene_pois = client.snapshot("s0").pois;
  client.add_task("s0", "copies", std::vector<Vec3>(scene_pois.begin(), scene_pois.begin() + 5));
  const SceneStatus copied = client.wait_idle("s0", {}, kLong);
  ASSERT_EQ(copied.tasks, 2u) << copied.last_error;
  EXPECT_EQ(copied.version, added.version) << "copies of covered POIs need no guard";
  EXPECT_TRUE(eventually([&] { return replica.roadmap().poi_count() == copied.poi_count; }, std::chrono::seconds(20),
                         "the replica learns of the second task"));
  EXPECT_EQ(roadmap_digest(replica.roadmap()), roadmap_digest(client.snapshot("s0").roadmap));
  EXPECT_EQ(daemon->terminate(), 0);
}

TEST_F(ServiceTest, KillNineDuringATaskAdditionLeavesBeforeOrAfterItAndTheRestartFinishesIt) {
  const std::uint64_t want = task_reference(scene_dir_ / "s0.yaml", BuildMethod::ispars, 20000, 300, 3);
  std::size_t before = 0, after = 0;  // kills that found the task not committed yet, or committed
  for (const int delay_ms : {0, 2, 5, 10, 20, 40, 80}) {
    TempDir data;
    const std::vector<std::string> quick{"--discovery-wait-ms", "100"};
    auto daemon = std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, data.path(), scene_dir_, "d", quick);
    {
      Client client(client_options(domain_));
      client.load("s0");
      client.build("s0", build_of("ispars", 20000));
      ASSERT_EQ(client.wait_idle("s0", {}, kLong).state, SceneState::idle);
      client.add_sampled_task("s0", "welds", 300, 3);
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));  // the kill's moment
      daemon->kill9();
    }
    daemon = std::make_unique<DaemonProcess>(ISPARS_DAEMON, domain_, data.path(), scene_dir_, "d", quick);
    Client client(client_options(domain_));
    // Loaded at start with its stored roadmap: before or after the task, never a roadmap with
    // the task's POIs and only some of its guards (recovery checks every commit whole).
    const SceneStatus recovered = client.stats("s0");
    ASSERT_NE(recovered.state, SceneState::failed) << recovered.last_error;
    (recovered.tasks == 1 ? after : before) += 1;
    // The accepted addition was recorded: the restart resumes it if it had not committed.
    const SceneStatus done = client.wait_idle("s0", {}, kLong);
    ASSERT_EQ(done.tasks, 1u) << "kill after " << delay_ms << " ms: " << done.last_error;
    EXPECT_EQ(done.samples_done, 20000u);
    EXPECT_EQ(roadmap_digest(client.snapshot("s0").roadmap), want) << "kill after " << delay_ms << " ms";
    EXPECT_EQ(client.verify("s0").verify.violations, 0u);
    EXPECT_EQ(daemon->terminate(), 0);
  }
  std::printf("kills with the task not yet committed: %zu, committed: %zu\n", before, after);
}

}  // namespace
}  // namespace ispars::test
