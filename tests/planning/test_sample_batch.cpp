// prepare_samples and skip_samples (sample_batch.hpp): the samples are the rng's uniform_in
// draws in order, each checked and given its POIs exactly as the scene answers for it alone,
// whatever the thread count; skip_samples leaves the rng where prepare_samples does.

#include <gtest/gtest.h>

#include "ispars/planning/builders/sample_batch.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

// open_scene's wall (x = 2.5, |y|, |z| <= 1), sampled in |x|, |y|, |z| <= 3, with two POIs by it
// at (2, 0, 0) and (2.7, 0, 0) (either side of the wall) and sensor range 1.2: some samples are
// invalid, and the valid ones see none or some of them.
const Scene& wall_box_scene() {
  static const test::TempDir dir;
  static const Scene scene = [] {
    const Scene base = test::open_scene(1.0, 2.0, true);
    scene_files::SceneConfig config = base.config();
    config.bounds = {Vec3(-3, -3, -3), Vec3(3, 3, 3)};
    config.sensor_range = 1.2;
    config.pois.file = dir.write("pois.txt", "2 0 0\n2.7 0 0\n");
    return Scene::build(config, base.mesh());
  }();
  return scene;
}

TEST(SampleBatch, SamplesAreTheRngsDrawsCheckedOneByOne) {
  const Scene& scene = wall_box_scene();
  scene_files::Rng rng(17), reference(17);
  std::vector<PreparedSample> out;
  prepare_samples(scene, rng, 400, 1, out);
  ASSERT_EQ(out.size(), 400u);
  std::size_t invalid = 0, seeing = 0;
  for (const PreparedSample& s : out) {
    EXPECT_EQ(s.q, reference.uniform_in(scene.config().bounds));
    EXPECT_EQ(s.valid, scene.point_valid(s.q));
    if (s.valid) {
      EXPECT_EQ(s.visible, scene.visibility().visible_pois(s.q));
      seeing += s.visible.empty() ? 0 : 1;
    } else {
      EXPECT_TRUE(s.visible.empty());
      ++invalid;
    }
  }
  EXPECT_GT(invalid, 0u) << "no sample fell by the wall: the test would not see invalid samples";
  EXPECT_GT(seeing, 0u) << "no sample saw a POI: the test would not see visible lists";
  EXPECT_EQ(rng.next_u64(), reference.next_u64()) << "exactly three draws a sample";
}

TEST(SampleBatch, AReusedBatchIsOverwrittenWhole) {
  const Scene& scene = wall_box_scene();
  std::vector<PreparedSample> out(500, PreparedSample{Vec3(9, 9, 9), true, {0, 1}});
  scene_files::Rng rng(3);
  prepare_samples(scene, rng, 300, 1, out);
  ASSERT_EQ(out.size(), 300u);
  for (const PreparedSample& s : out) {
    if (s.valid) {
      EXPECT_EQ(s.visible, scene.visibility().visible_pois(s.q));
    } else {
      EXPECT_TRUE(s.visible.empty()) << "a stale POI list survived";
    }
  }
  prepare_samples(scene, rng, 0, 4, out);
  EXPECT_TRUE(out.empty());
}

TEST(SampleBatch, AnyThreadCountGivesTheSameBatch) {
  const Scene& scene = wall_box_scene();
  std::vector<PreparedSample> one;
  scene_files::Rng a(29);
  prepare_samples(scene, a, 1000, 1, one);
  const std::uint64_t next = a.next_u64();
  for (const unsigned threads : {0u, 2u, 3u, 8u}) {
    scene_files::Rng b(29);
    std::vector<PreparedSample> many;
    prepare_samples(scene, b, 1000, threads, many);
    ASSERT_EQ(many.size(), one.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < one.size(); ++i) {
      differ += (many[i].q != one[i].q || many[i].valid != one[i].valid || many[i].visible != one[i].visible) ? 1 : 0;
    }
    EXPECT_EQ(differ, 0u) << threads << " threads";
    EXPECT_EQ(b.next_u64(), next) << threads << " threads";
  }
}

TEST(SampleBatch, SkipSamplesLeavesTheRngWherePrepareSamplesDoes) {
  const Scene& scene = wall_box_scene();
  for (const std::size_t count : {std::size_t{0}, std::size_t{1}, std::size_t{257}}) {
    scene_files::Rng prepared(41), skipped(41);
    std::vector<PreparedSample> out;
    prepare_samples(scene, prepared, count, 2, out);
    skip_samples(skipped, count);
    EXPECT_EQ(prepared.next_u64(), skipped.next_u64()) << count << " samples";
  }
}

}  // namespace
}  // namespace ispars::planning
