// TaskBoard: other daemons' tasks kept for a takeover. It answers only with a scene's whole task
// list of one generation, and ignores what is out of bounds.

#include <gtest/gtest.h>

#include <limits>

#include "ispars/server/task_board.hpp"

namespace ispars::server {
namespace {

msg::SceneTask task(std::uint32_t index, std::uint64_t generation, const std::string& name, std::size_t pois,
                    bool removed = false) {
  msg::SceneTask t;
  t.scene("s");
  t.index(index);
  t.server_id("a");
  t.generation(generation);
  t.name(name);
  t.removed(removed);
  for (std::size_t i = 0; i < pois; ++i) {
    msg::Point p;
    p.x(static_cast<double>(i));
    t.pois().push_back(p);
  }
  return t;
}

TEST(TaskBoard, AScenesTasksComeWholeOrNotAtAll) {
  TaskBoard board;
  board.seen(task(0, 7, "a", 3, true));
  EXPECT_EQ(board.tasks_of("s", "a", 7, 3, 7), std::nullopt) << "task 1 has not arrived";
  board.seen(task(1, 7, "b", 4));
  const auto both = board.tasks_of("s", "a", 7, 3, 7);
  ASSERT_TRUE(both.has_value());
  ASSERT_EQ(both->size(), 2u);
  EXPECT_TRUE((*both)[0].removed);
  EXPECT_EQ((*both)[1].name, "b");
  EXPECT_EQ((*both)[1].pois.size(), 4u);
  EXPECT_EQ(board.tasks_of("s", "a", 8, 3, 7), std::nullopt) << "another generation's roadmap";
  EXPECT_EQ(board.tasks_of("s", "a", 7, 3, 8), std::nullopt) << "POIs that do not add up";
  EXPECT_EQ(board.tasks_of("t", "a", 7, 3, 7), std::nullopt);
  // A later generation (a replacing build keeps the tasks) replaces them index by index.
  board.seen(task(0, 9, "a", 3, true));
  EXPECT_EQ(board.tasks_of("s", "a", 9, 3, 7), std::nullopt);
  board.seen(task(1, 9, "b", 4));
  EXPECT_TRUE(board.tasks_of("s", "a", 9, 3, 7).has_value());
  EXPECT_EQ(board.size(), 2u);
}

// The two sides of a partition publish different tasks at one index: each daemon's list is kept.
TEST(TaskBoard, TwoDaemonsTasksAtOneIndexAreKeptApart) {
  TaskBoard board;
  board.seen(task(0, 7, "mine", 2));
  msg::SceneTask theirs = task(0, 7, "theirs", 5);
  theirs.server_id("b");
  board.seen(theirs);
  const auto a = board.tasks_of("s", "a", 7, 1, 2);
  const auto b = board.tasks_of("s", "b", 7, 1, 5);
  ASSERT_TRUE(a.has_value());
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ((*a)[0].name, "mine");
  EXPECT_EQ((*b)[0].name, "theirs");
}

TEST(TaskBoard, ATaskOutOfBoundsIsIgnored) {
  TaskBoard board;
  board.seen(task(service::kMaxTasks, 7, "far", 1));
  board.seen(task(0, 7, "../x", 1));
  board.seen(task(0, 7, "big", service::kMaxTaskPois + 1));
  board.seen(task(0, 7, "none", 0));
  msg::SceneTask nan = task(0, 7, "nan", 1);
  nan.pois()[0].y(std::numeric_limits<double>::quiet_NaN());
  board.seen(nan);
  EXPECT_EQ(board.size(), 0u);
}

}  // namespace
}  // namespace ispars::server
