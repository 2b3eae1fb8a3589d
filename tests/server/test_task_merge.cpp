// merge_tasks: the loser's task changes carried into the winner's list of the same lineage.

#include <gtest/gtest.h>

#include "ispars/server/task_merge.hpp"

namespace ispars::server {
namespace {

service::InspectionTask task(const std::string& name, double x, bool removed = false) {
  return service::InspectionTask{name, {Vec3(x, 0, 0)}, removed};
}

TEST(TaskMerge, ATaskAddedOnTheLosingSideIsAdded) {
  const std::vector<service::InspectionTask> mine{task("a", 1)};
  const std::vector<service::InspectionTask> theirs{task("a", 1), task("b", 2)};
  const TaskMerge m = merge_tasks(mine, theirs);
  ASSERT_EQ(m.add.size(), 1u);
  EXPECT_EQ(m.add[0].name, "b");
  EXPECT_TRUE(m.remove.empty());
}

TEST(TaskMerge, ATaskRemovedOnTheLosingSideIsRemoved) {
  const std::vector<service::InspectionTask> mine{task("a", 1), task("b", 2)};
  const std::vector<service::InspectionTask> theirs{task("a", 1, true), task("b", 2)};
  const TaskMerge m = merge_tasks(mine, theirs);
  EXPECT_TRUE(m.add.empty());
  EXPECT_EQ(m.remove, std::vector<std::string>{"a"});
}

TEST(TaskMerge, TheWinnersOwnChangesStand) {
  // The winner removed a (the loser still holds it), and added c with other POIs than the
  // loser's c: nothing changes; a removed and added again on the loser is held there: kept.
  const std::vector<service::InspectionTask> mine{task("a", 1, true), task("c", 3)};
  const std::vector<service::InspectionTask> theirs{task("a", 1), task("c", 4), task("d", 5, true), task("d", 6)};
  const TaskMerge m = merge_tasks(mine, theirs);
  ASSERT_EQ(m.add.size(), 1u);
  EXPECT_EQ(m.add[0].name, "d");
  EXPECT_EQ(m.add[0].pois[0].x(), 6);
  EXPECT_TRUE(m.remove.empty());
  EXPECT_TRUE(merge_tasks(mine, mine).empty());
}

}  // namespace
}  // namespace ispars::server
