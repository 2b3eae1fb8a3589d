// The flown-tour pipeline (flown_tour.hpp) on a real scene: no stage lengthens the tour, the
// result passes the independent check, the same options give the same tour, and a stop ends it
// within half a second with a sound tour.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/planning/tour/flown_tour.hpp"
#include "support/test_support.hpp"

namespace ispars::planning {
namespace {

constexpr std::size_t kSamples = 3000;

const SparsBuilder& water_tower_roadmap() {
  static const auto builder = [] {
    BuildOptions build;
    build.seed = 2;
    auto b = std::make_unique<SparsBuilder>(test::shared_scene("water_tower"), build,
                                            SparsRules::for_variant(SparsVariant::stretch, true));
    b->extend(kSamples);
    return b;
  }();
  return *builder;
}

FlownTourOptions equal_work() {
  FlownTourOptions o;
  o.search.max_iterations = 300;
  o.search.budget_seconds = 120;
  o.search.lp_bound = false;
  o.search.seed = 5;
  o.build_samples = kSamples;
  return o;
}

TEST(FlownTour, NoStageLengthensTheTourAndTheFlownTourPassesTheCheck) {
  const Scene& scene = test::shared_scene("water_tower");
  const Roadmap& roadmap = water_tower_roadmap().roadmap();
  const InspectionGraph graph = InspectionGraph::from_roadmap(roadmap);
  const FlownTour t = fly_tour(scene, graph, roadmap.positions(), equal_work());
  ASSERT_GE(t.stages.size(), 4u);
  EXPECT_EQ(t.stages[0].name, "walk");
  EXPECT_EQ(t.stages[1].name, "shortcut");
  EXPECT_EQ(t.stages[2].name, "corridor");
  EXPECT_EQ(t.stages.back().name, "refine");
  for (std::size_t i = 1; i < t.stages.size(); ++i) {
    EXPECT_LE(t.stages[i].cost, t.stages[i - 1].cost + 1e-9) << t.stages[i].name;
  }
  EXPECT_LT(t.cost, t.walk_cost);
  EXPECT_TRUE(t.check.valid()) << t.check.problem;
  EXPECT_EQ(t.check.sees.size(), t.stops.size());
  EXPECT_EQ(t.stops.front(), scene.config().root);
  EXPECT_GE(t.graph_vertices, graph.vertex_count());
}

TEST(FlownTour, TheSameOptionsGiveTheSameTour) {
  const Scene& scene = test::shared_scene("water_tower");
  const Roadmap& roadmap = water_tower_roadmap().roadmap();
  const InspectionGraph graph = InspectionGraph::from_roadmap(roadmap);
  const FlownTour a = fly_tour(scene, graph, roadmap.positions(), equal_work());
  const FlownTour b = fly_tour(scene, graph, roadmap.positions(), equal_work());
  EXPECT_EQ(a.stops, b.stops);
  EXPECT_EQ(a.cost, b.cost);
}

TEST(FlownTour, AStopEndsItWithinHalfASecondWithASoundTour) {
  const Scene& scene = test::shared_scene("water_tower");
  const Roadmap& roadmap = water_tower_roadmap().roadmap();
  const InspectionGraph graph = InspectionGraph::from_roadmap(roadmap);
  // A 3 s budget: the search until 1.5 s, the corridor until 2.55 s, then refinement.
  for (const double after : {0.3, 1.8, 2.7}) {
    std::atomic<bool> stop{false};
    FlownTourOptions o = equal_work();
    o.search.max_iterations = 0;
    o.search.budget_seconds = 3;
    o.search.stop = &stop;
    std::chrono::steady_clock::time_point stopped_at;
    std::thread stopper([&] {
      std::this_thread::sleep_for(std::chrono::duration<double>(after));  // the moment to test, not a wait
      stopped_at = std::chrono::steady_clock::now();
      stop = true;
    });
    const FlownTour t = fly_tour(scene, graph, roadmap.positions(), o);
    const auto returned = std::chrono::steady_clock::now();
    stopper.join();
    EXPECT_LT(std::chrono::duration<double>(returned - stopped_at).count(), 0.5) << "stopped after " << after << " s";
    EXPECT_TRUE(t.check.valid()) << t.check.problem;
  }
}

TEST(FlownTour, AnotherScenesRoadmapIsRefused) {
  const Roadmap& roadmap = water_tower_roadmap().roadmap();
  const InspectionGraph graph = InspectionGraph::from_roadmap(roadmap);
  EXPECT_THROW((void)fly_tour(test::shared_scene("truss_bridge"), graph, roadmap.positions(), equal_work()),
               std::invalid_argument);
}

}  // namespace
}  // namespace ispars::planning
