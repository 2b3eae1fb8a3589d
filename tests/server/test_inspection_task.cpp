// Inspection tasks' rules: names, POIs on the structure, sampling, coverage per task, and what a
// removed task leaves.

#include <gtest/gtest.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/inspection_task.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

const planning::Scene& tank_tower() { return test::shared_scene("demo_tank_tower"); }

std::string field_of(const planning::Scene& scene, const std::vector<InspectionTask>& tasks,
                     const InspectionTask& task) {
  try {
    check_task(scene, tasks, task);
  } catch (const params::InputError& e) {
    return e.field();
  }
  return "(accepted)";
}

TEST(InspectionTask, NamesFollowTheSceneNameRule) {
  EXPECT_TRUE(valid_task_name("welds-2026.11_a"));
  EXPECT_FALSE(valid_task_name(""));
  EXPECT_FALSE(valid_task_name(".hidden"));
  EXPECT_FALSE(valid_task_name("a/b"));
  EXPECT_FALSE(valid_task_name(std::string(65, 'a')));
  EXPECT_TRUE(valid_task_name(std::string(64, 'a')));
}

TEST(InspectionTask, SampledPoisLieOnTheSurfaceAndEachRuleNamesItsField) {
  const std::vector<Vec3> pois = sample_task_pois(tank_tower(), 200, 9);
  ASSERT_EQ(pois.size(), 200u);
  EXPECT_EQ(pois, sample_task_pois(tank_tower(), 200, 9)) << "a seed gives the same POIs";
  EXPECT_NE(pois, sample_task_pois(tank_tower(), 200, 10));
  const InspectionTask good{"good", pois};
  EXPECT_EQ(field_of(tank_tower(), {}, good), "(accepted)");
  EXPECT_EQ(field_of(tank_tower(), {good}, good), "task.name");
  EXPECT_EQ(field_of(tank_tower(), {}, {"bad name", pois}), "task.name");
  EXPECT_EQ(field_of(tank_tower(), {}, {"empty", {}}), "task.pois");
  EXPECT_EQ(field_of(tank_tower(), {}, {"many", std::vector<Vec3>(kMaxTaskPois + 1, pois[0])}), "task.pois");
  // Moved off the structure (along an axis that leads away from every surface), it is refused.
  InspectionTask lifted = good;
  for (const Vec3& step : {Vec3(0.3, 0, 0), Vec3(-0.3, 0, 0), Vec3(0, 0.3, 0), Vec3(0, -0.3, 0)}) {
    if (tank_tower().collision().distance_to_surface(good.pois[17] + step) > 3 * kTaskPoiSurfaceTolerance) {
      lifted.pois[17] += step;
      break;
    }
  }
  ASSERT_NE(lifted.pois[17], good.pois[17]) << "no step leads off the structure";
  EXPECT_EQ(field_of(tank_tower(), {}, lifted), "task.pois[17]");
  InspectionTask nudged = good;
  nudged.pois[17].z() += kTaskPoiSurfaceTolerance / 4;  // within the tolerance: still on the structure
  EXPECT_EQ(field_of(tank_tower(), {}, nudged), "(accepted)");
  std::vector<InspectionTask> full;
  for (std::size_t i = 0; i < kMaxTasks; ++i) {
    std::string name = std::to_string(i);  // (not "t" + ...: GCC 12's -Wrestrict false alarm)
    full.push_back({name.insert(0, 1, 't'), {pois[0]}});
  }
  EXPECT_EQ(field_of(tank_tower(), full, {"one-more", {pois[0]}}), "task");
  EXPECT_THROW((void)sample_task_pois(tank_tower(), 0, 1), params::InputError);
  EXPECT_THROW((void)sample_task_pois(tank_tower(), kMaxTaskPois + 1, 1), params::InputError);
}

TEST(InspectionTask, CoverageAndTargetsCountOnlyTheTasksOwnPois) {
  // Vertex 0 (the root) and 1 share a component; vertex 2 is alone.
  const std::size_t scene_pois = 3;
  Roadmap roadmap(scene_pois + 5);
  roadmap.add_vertex(Vec3::Zero(), std::vector<PoiId>{0, 3});
  roadmap.add_vertex(Vec3(1, 0, 0), std::vector<PoiId>{4});
  roadmap.add_vertex(Vec3(9, 0, 0), std::vector<PoiId>{6, 7});
  roadmap.add_edge(0, 1);
  const std::vector<InspectionTask> tasks{{"a", {Vec3::Zero(), Vec3::Zero()}},
                                          {"b", {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}}};
  const std::vector<TaskCoverage> c = task_coverage(roadmap, scene_pois, tasks);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].first_poi, 3u);
  EXPECT_EQ(c[0].covered, 2u);
  EXPECT_EQ(c[0].covered_root, 2u);
  EXPECT_EQ(c[1].first_poi, 5u);
  EXPECT_EQ(c[1].covered, 2u);
  EXPECT_EQ(c[1].covered_root, 0u);
  EXPECT_EQ(task_targets(roadmap, scene_pois, tasks, "a"), (std::vector<PoiId>{3, 4}));
  EXPECT_THROW((void)task_targets(roadmap, scene_pois, tasks, "b"), params::InputError) << "none seen from the root";
  EXPECT_THROW((void)task_targets(roadmap, scene_pois, tasks, "c"), params::InputError) << "no such task";
}

// Vertex 0 (the root) sees scene POI 0 and POIs 3-4 (task a); vertex 1, in its component, sees
// POI 5 (task b) and 1; vertex 2, alone, sees 2.
Roadmap two_task_roadmap() {
  Roadmap roadmap(3 + 4);
  roadmap.add_vertex(Vec3::Zero(), std::vector<PoiId>{0, 3, 4});
  roadmap.add_vertex(Vec3(1, 0, 0), std::vector<PoiId>{1, 5});
  roadmap.add_vertex(Vec3(9, 0, 0), std::vector<PoiId>{2});
  roadmap.add_edge(0, 1);
  return roadmap;
}

TEST(InspectionTask, ARemovedTaskLeavesEveryTargetSetAndFreesItsName) {
  const Roadmap roadmap = two_task_roadmap();
  std::vector<InspectionTask> tasks{{"a", {Vec3::Zero(), Vec3::Zero()}}, {"b", {Vec3::Zero(), Vec3::Zero()}}};
  EXPECT_TRUE(live_targets(roadmap, 3, tasks).empty()) << "no task removed: every POI seen is a target";
  tasks[0].removed = true;
  EXPECT_EQ(live_targets(roadmap, 3, tasks), (std::vector<PoiId>{0, 1, 5})) << "task a's 3 and 4 left out";
  const std::vector<TaskCoverage> c = task_coverage(roadmap, 3, tasks);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].name, "b");
  EXPECT_EQ(c[0].first_poi, 5u) << "a removed task's POIs keep their ids";
  EXPECT_EQ(task_targets(roadmap, 3, tasks, "b"), (std::vector<PoiId>{5}));
  try {
    (void)task_targets(roadmap, 3, tasks, "a");
    ADD_FAILURE() << "a removed task's targets";
  } catch (const params::InputError& e) {
    EXPECT_EQ(e.field(), "task");
    EXPECT_NE(std::string(e.what()).find("task 'a' was removed already"), std::string::npos) << e.what();
  }
  EXPECT_EQ(live_task(tasks, "b"), 1u);
  EXPECT_THROW((void)live_task(tasks, "a"), params::InputError);
  EXPECT_THROW((void)live_task(tasks, "nope"), params::InputError);
  // The name is free again; the new task is the live one of that name.
  const InspectionTask again{"a", sample_task_pois(tank_tower(), 3, 1)};
  EXPECT_EQ(field_of(tank_tower(), tasks, again), "(accepted)");
  tasks.push_back(again);
  EXPECT_EQ(live_task(tasks, "a"), 2u);
  // Only removed tasks' POIs seen: no target is left, and the tour is refused by name.
  Roadmap only_a(3 + 2);
  only_a.add_vertex(Vec3::Zero(), std::vector<PoiId>{3});
  std::vector<InspectionTask> one{{"a", {Vec3::Zero(), Vec3::Zero()}, true}};
  EXPECT_THROW((void)live_targets(only_a, 3, one), params::InputError);
}

}  // namespace
}  // namespace ispars::service
