#pragma once
// The roadmap store's test fixture: a bridge scene's Inspection-SPARS build, committed step by
// step, and the states recovery must reproduce.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ispars/service/roadmap_store.hpp"
#include "support/test_support.hpp"

namespace ispars::service {

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void spit(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline RoadmapsView view(const planning::RoadmapBuilder& b) {
  return {b.samples(), &b.roadmap(), b.dense(), b.dense_ids()};
}

// A committed state of the build: what recovery must reproduce.
struct Committed {
  std::uint64_t samples;
  std::uint64_t digest;
  std::uint64_t dense_digest;
  std::size_t ids;
};

class RoadmapStoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = &test::shared_scene("truss_bridge");
    recipe_.scene = "bridge";
    recipe_.method = BuildMethod::ispars;
    recipe_.seed = 11;
    recipe_.dense_delta = scene_->config().dense_delta;
    recipe_.sparse_delta = scene_->config().sparse_delta;
    recipe_.stretch = scene_->config().stretch;
    recipe_.generation = 42;
  }
  // Builds in `commits` steps of `step` samples, committing each; returns every committed state.
  std::vector<Committed> build_and_commit(RoadmapStore& store, int commits, std::size_t step) {
    planning::BuildOptions options;
    options.seed = recipe_.seed;
    builder_ = planning::make_roadmap_builder(BuildMethod::ispars, *scene_, options);
    std::vector<Committed> states;
    std::uint64_t v = 0, dv = 0;
    for (int i = 0; i < commits; ++i) {
      if (i > 0) builder_->extend(step);
      const BuildCommit c = commit_since(view(*builder_), v, dv);
      store.commit(c);
      store.wait_for_compaction();  // the journals' split is then the same every run
      v = builder_->roadmap().version();
      dv = builder_->dense()->version();
      states.push_back({builder_->samples(), roadmap_digest(builder_->roadmap()), roadmap_digest(*builder_->dense()),
                        builder_->dense_ids().size()});
    }
    return states;
  }
  static void expect_state(const StoreRecovery& r, const Committed& c) {
    EXPECT_EQ(r.roadmaps.samples, c.samples);
    EXPECT_EQ(roadmap_digest(r.roadmaps.roadmap), c.digest);
    ASSERT_TRUE(r.roadmaps.dense.has_value());
    EXPECT_EQ(roadmap_digest(*r.roadmaps.dense), c.dense_digest);
    EXPECT_EQ(r.roadmaps.dense_ids.size(), c.ids);
  }

  const planning::Scene* scene_ = nullptr;
  RoadmapRecipe recipe_;
  std::unique_ptr<planning::RoadmapBuilder> builder_;
  test::TempDir dir_;
};

}  // namespace ispars::service
