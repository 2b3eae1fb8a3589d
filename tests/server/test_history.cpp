// The history checker (tests/support/history.hpp) on made-up histories: what it must find
// missing, and what it must let pass (unacknowledged changes, lineages a later build replaced).

#include <gtest/gtest.h>

#include "support/history.hpp"

namespace ispars::test {
namespace {

using Kind = HistoryOp::Kind;

HistoryOp op(Kind kind, bool acknowledged, std::uint64_t generation, std::uint64_t target, std::string task = "") {
  HistoryOp o;
  o.kind = kind;
  o.acknowledged = acknowledged;
  o.generation = generation;
  o.target = target;
  o.task = std::move(task);
  o.server = "d1";
  o.what = "op";
  return o;
}

HistoryRead read(std::uint64_t generation, std::uint64_t samples, std::vector<std::string> tasks = {}) {
  return HistoryRead{"d2", generation, samples, std::move(tasks)};
}

TEST(History, AReadWithEveryAcknowledgedChangeMissesNothing) {
  const std::vector<HistoryOp> h{op(Kind::build, true, 10, 800), op(Kind::extend, true, 10, 1100),
                                 op(Kind::add_task, true, 10, 1100, "t1"), op(Kind::add_task, true, 10, 1100, "t2"),
                                 op(Kind::remove_task, true, 10, 1100, "t1")};
  EXPECT_TRUE(missing_from(h, read(10, 1100, {"t2"})).empty());
  EXPECT_TRUE(missing_from(h, read(10, 1500, {"t2"})).empty()) << "more samples than acknowledged are allowed";
}

TEST(History, AnAcknowledgedExtendNotReachedIsMissing) {
  const std::vector<HistoryOp> h{op(Kind::build, true, 10, 800), op(Kind::extend, true, 10, 1100)};
  const auto missing = missing_from(h, read(10, 800));
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_NE(missing[0].find("target 1100"), std::string::npos) << missing[0];
}

TEST(History, AnUnacknowledgedChangeMayBeMissingOrPresent) {
  const std::vector<HistoryOp> h{op(Kind::build, true, 10, 800), op(Kind::extend, false, 10, 1100),
                                 op(Kind::add_task, false, 10, 800, "t1")};
  EXPECT_TRUE(missing_from(h, read(10, 800)).empty());
  EXPECT_TRUE(missing_from(h, read(10, 1100, {"t1"})).empty());
}

TEST(History, TasksFollowTheirLastAcknowledgedChange) {
  const std::vector<HistoryOp> h{op(Kind::build, true, 10, 800), op(Kind::add_task, true, 10, 800, "t1"),
                                 op(Kind::remove_task, true, 10, 800, "t1"), op(Kind::add_task, true, 10, 800, "t2")};
  EXPECT_EQ(missing_from(h, read(10, 800, {"t1", "t2"})).size(), 1u) << "t1 was removed";
  EXPECT_EQ(missing_from(h, read(10, 800, {})).size(), 1u) << "t2 was added";
  EXPECT_TRUE(missing_from(h, read(10, 800, {"t2"})).empty());
}

TEST(History, AnOlderLineageOrOneNobodyAcknowledgedIsMissingTheLatestBuild) {
  const std::vector<HistoryOp> h{op(Kind::build, true, 10, 800), op(Kind::extend, true, 10, 1100),
                                 op(Kind::build, true, 20, 600)};
  EXPECT_TRUE(missing_from(h, read(20, 600)).empty()) << "the build replaced generation 10 and its extend";
  EXPECT_FALSE(missing_from(h, read(10, 1100)).empty()) << "generation 20 was acknowledged";
  EXPECT_FALSE(missing_from(h, read(30, 600)).empty()) << "nobody acknowledged a build of generation 30";
}

}  // namespace
}  // namespace ispars::test
