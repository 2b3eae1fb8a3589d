// Every builder: deterministic by seed, split-invariant under extend, thread-count-invariant,
// and geometrically clean on every kind of scene.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/scene_files/procedural.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

const std::vector<BuildMethod> kMethods{BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars,
                                        BuildMethod::irisc};

std::string build_fingerprint(const Scene& scene, BuildMethod method, std::uint64_t seed, unsigned threads,
                              const std::vector<std::size_t>& steps) {
  BuildOptions options;
  options.seed = seed;
  options.threads = threads;
  auto builder = make_roadmap_builder(method, scene, options);
  for (const std::size_t n : steps) builder->extend(n);
  std::string print = test::fingerprint(builder->roadmap());
  if (builder->dense() != nullptr) print += "dense\n" + test::fingerprint(*builder->dense());
  return print;
}

TEST(RoadmapBuilder, MethodNamesRoundTrip) {
  for (const BuildMethod m : kMethods) EXPECT_EQ(parse_build_method(to_string(m)), m);
  EXPECT_FALSE(parse_build_method("prm").has_value());
}

TEST(RoadmapBuilder, SameSeedSameRoadmapOtherSeedOtherRoadmap) {
  const Scene& scene = test::shared_scene("water_tower");
  for (const BuildMethod m : kMethods) {
    const std::string a = build_fingerprint(scene, m, 3, 1, {1500});
    EXPECT_EQ(a, build_fingerprint(scene, m, 3, 1, {1500})) << to_string(m);
    EXPECT_NE(a, build_fingerprint(scene, m, 4, 1, {1500})) << to_string(m);
  }
}

TEST(RoadmapBuilder, ExtendingEqualsOneLongerRun) {
  const Scene& scene = test::shared_scene("truss_bridge");
  for (const BuildMethod m : kMethods) {
    const std::string whole = build_fingerprint(scene, m, 5, 1, {2000});
    EXPECT_EQ(whole, build_fingerprint(scene, m, 5, 1, {700, 1300})) << to_string(m);
    EXPECT_EQ(whole, build_fingerprint(scene, m, 5, 1, {1, 255, 256, 257, 1231})) << to_string(m);
  }
}

// The Dense method restarts without replay: a builder resumed from the roadmap alone (as the
// store gives it back, from its batches) goes on as the uninterrupted one, from any point.
TEST(RoadmapBuilder, AResumedDenseBuilderGoesOnByteForByteAsTheUninterruptedOne) {
  for (const std::string name : {"water_tower", "caric_city"}) {
    const Scene& scene = test::shared_scene(name);
    BuildOptions options;
    options.seed = 5;
    auto whole = make_roadmap_builder(BuildMethod::dense, scene, options);
    std::unique_ptr<RoadmapBuilder> resumed;
    for (const std::size_t n : {0u, 1u, 300u, 1201u}) {
      whole->extend(n);
      if (resumed) resumed->extend(n);
      const Roadmap& source = resumed ? resumed->roadmap() : whole->roadmap();
      Roadmap stored(scene.pois().size());
      apply_batch(stored, batch_since(source, 0));
      resumed =
          resume_roadmap_builder(BuildMethod::dense, scene, options, {whole->samples(), std::move(stored), {}, {}});
      ASSERT_EQ(roadmap_digest(resumed->roadmap()), roadmap_digest(whole->roadmap())) << name;
    }
    resumed->extend(1500);
    whole->extend(1500);
    EXPECT_EQ(roadmap_digest(resumed->roadmap()), roadmap_digest(whole->roadmap())) << name;
    EXPECT_GT(resumed->roadmap().edge_count(), 1000u) << name;
  }
}

TEST(RoadmapBuilder, ThreadCountDoesNotChangeTheRoadmap) {
  const Scene& scene = test::shared_scene("radio_tower");
  for (const BuildMethod m : kMethods) {
    EXPECT_EQ(build_fingerprint(scene, m, 7, 1, {1500}), build_fingerprint(scene, m, 7, 2, {1500})) << to_string(m);
    EXPECT_EQ(build_fingerprint(scene, m, 7, 1, {1500}), build_fingerprint(scene, m, 7, 3, {600, 900})) << to_string(m);
  }
}

TEST(RoadmapBuilder, EveryMethodBuildsCleanRoadmapsOnProceduralScenes) {
  // Also the "no exceptions on any input" guard: several seeds, every kind, zero samples too.
  for (const auto& kind : scene_files::procedural_kinds()) {
    for (std::uint64_t seed : {1, 2}) {
      const Scene scene = Scene::build(scene_files::procedural_scene_config(kind, seed));
      for (const BuildMethod m : kMethods) {
        BuildOptions options;
        options.seed = seed;
        auto builder = make_roadmap_builder(m, scene, options);
        builder->extend(0);
        EXPECT_EQ(builder->roadmap().vertex_count(), 1u) << "the root alone";
        builder->extend(test::scaled(1200));
        const VerificationReport report =
            builder->dense() ? verify_sparse_pair(scene, builder->roadmap(), *builder->dense(), builder->dense_ids())
                             : verify_roadmap(scene, builder->roadmap());
        EXPECT_TRUE(report.geometry_ok()) << kind << " " << to_string(m);
        EXPECT_EQ(builder->roadmap().position(0), scene.config().root);
        EXPECT_GT(builder->roadmap().vertex_count(), 10u) << kind << " " << to_string(m);
      }
    }
  }
}

TEST(RoadmapBuilder, AllSamplesInvalidLeavesTheRoot) {
  // A robot almost as wide as the hollow box it sits in: only a 0.1 m cube around the centre is
  // valid, so practically every sample is dropped; nothing breaks.
  scene_files::TriangleMesh mesh;
  scene_files::add_box(mesh, Vec3(0, 0, 0), Vec3(10, 10, 10));
  scene_files::SceneConfig config = scene_files::procedural_scene_config("city_grid", 1);
  config.procedural.reset();
  config.bounds = {Vec3(-10.2, -10.2, -10.2), Vec3(10.2, 10.2, 10.2)};
  config.robot_radius = 9.9;
  config.root = Vec3(0, 0, 0);
  const Scene scene = Scene::build(config, mesh);
  for (const BuildMethod m : kMethods) {
    auto builder = make_roadmap_builder(m, scene, BuildOptions{});
    builder->extend(500);
    EXPECT_GE(builder->roadmap().vertex_count(), 1u);
    EXPECT_EQ(builder->samples(), 500u);
  }
}

}  // namespace
}  // namespace ispars::planning
