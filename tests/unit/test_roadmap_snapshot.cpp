// Readers of a roadmap under construction see whole, consistent snapshots (OMPL's SPARS let its
// solution thread read vertex data while construction reallocated it).

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "ispars/roadmap_snapshot.hpp"
#include "ispars/spars_builder.hpp"
#include "support/test_support.hpp"

namespace ispars {
namespace {

TEST(RoadmapSnapshots, ReadersSeeConsistentRoadmapsWhileTheWriterBuilds) {
  const Scene& scene = test::shared_scene("water_tower");
  SparsBuilder builder(scene, BuildOptions{}, SparsRules::for_variant(SparsVariant::stretch, true));
  RoadmapSnapshots snapshots;
  std::atomic<bool> done{false};
  std::atomic<std::size_t> reads{0};
  std::atomic<std::size_t> problems{0};
  std::atomic<std::size_t> growth_seen{0};

  const auto reader = [&] {
    std::uint64_t last_version = 0;
    while (!done.load()) {
      const std::shared_ptr<const Roadmap> g = snapshots.latest();
      // A snapshot is internally whole: the log, the vertices and the edges agree.
      if (g->version() != g->vertex_count() + g->edge_count()) ++problems;
      for (const RoadmapEdge& e : g->edges()) {
        if (e.u >= g->vertex_count() || e.v >= g->vertex_count() ||
            e.cost != (g->position(e.u) - g->position(e.v)).norm()) {
          ++problems;
        }
      }
      if (g->version() < last_version) ++problems;  // never goes back
      if (g->version() > last_version) ++growth_seen;
      last_version = g->version();
      ++reads;
    }
  };
  std::thread r1(reader);
  std::thread r2(reader);
  for (int batch = 0; batch < 30; ++batch) {
    builder.extend(100);
    snapshots.publish(builder.roadmap());
  }
  done = true;
  r1.join();
  r2.join();
  EXPECT_EQ(problems.load(), 0u);
  EXPECT_GT(reads.load(), 10u);
  EXPECT_GT(growth_seen.load(), 1u);
  EXPECT_EQ(snapshots.latest()->version(), builder.roadmap().version());
  EXPECT_EQ(test::fingerprint(*snapshots.latest()), test::fingerprint(builder.roadmap()));
}

TEST(RoadmapBuilder, StepTakesGivenSamplesWithoutTouchingTheStream) {
  const Scene& scene = test::shared_scene("truss_bridge");
  for (const BuildMethod m : {BuildMethod::dense, BuildMethod::spars, BuildMethod::ispars, BuildMethod::irisc}) {
    auto a = make_roadmap_builder(m, scene, BuildOptions{});
    auto b = make_roadmap_builder(m, scene, BuildOptions{});
    a->step(Vec3(-8, -12, 1.5));   // a valid sample near the root
    a->step(Vec3(0, 0, 0.1));      // inside the deck: dropped
    EXPECT_EQ(a->samples(), 0u);
    a->extend(500);
    b->extend(500);
    // The stream is untouched: the one extra valid sample is exactly one extra dense vertex.
    if (m == BuildMethod::dense) {
      EXPECT_EQ(a->roadmap().vertex_count(), b->roadmap().vertex_count() + 1);
    } else if (m != BuildMethod::irisc) {
      EXPECT_EQ(a->dense()->vertex_count(), b->dense()->vertex_count() + 1) << to_string(m);
    } else {
      EXPECT_GE(a->roadmap().vertex_count(), 2u);  // the RRG steered toward it and admitted it
    }
  }
}

}  // namespace
}  // namespace ispars
