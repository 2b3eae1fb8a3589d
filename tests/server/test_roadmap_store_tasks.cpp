// Inspection tasks in the roadmap store: a task's commit (the task, then its guards) survives
// reopening and compaction, also when it draws no sample past the snapshot's; so does a task's
// removal, which changes no vertex.

#include <gtest/gtest.h>

#include "ispars/planning/builders/poi_visibility.hpp"
#include "roadmap_store_fixture.hpp"

namespace ispars::service {
namespace {

class RoadmapStoreTaskTest : public RoadmapStoreTest {
 protected:
  // Adds a task of `count` surface POIs to the fixture's builder and commits it.
  void add_task(RoadmapStore& store, const std::string& name, std::size_t count, std::uint64_t seed) {
    const std::uint64_t v = builder_->roadmap().version();
    const std::uint64_t dv = builder_->dense()->version();
    InspectionTask task{name, sample_task_pois(*scene_, count, seed)};
    scenes_.push_back(std::make_unique<planning::Scene>(current().with_more_pois(task.pois)));
    builder_->add_pois(*scenes_.back());
    BuildCommit commit = commit_since(view(*builder_), v, dv);
    commit.tasks = {task};
    commit.task_count = ++tasks_;
    store.commit(commit);
  }
  // Removes task `index`: a commit of no vertex, edge or sample, as a session makes it.
  void remove_task(RoadmapStore& store, std::uint64_t index) {
    BuildCommit commit;
    commit.samples = builder_->samples();
    commit.roadmap.from_version = commit.roadmap.to_version = builder_->roadmap().version();
    commit.dense.from_version = commit.dense.to_version = builder_->dense()->version();
    commit.removed_tasks = {index};
    commit.task_count = ++tasks_;
    store.commit(commit);
  }
  const planning::Scene& current() const { return scenes_.empty() ? *scene_ : *scenes_.back(); }
  // What a session does after recovery: the vertices built before a task see its POIs too.
  void expect_builders_state(StoreRecovery& r) const {
    const auto first = static_cast<PoiId>(scene_->pois().size());
    planning::see_new_pois(r.roadmaps.roadmap, current(), first);
    planning::see_new_pois(*r.roadmaps.dense, current(), first);
    EXPECT_EQ(r.roadmaps.samples, builder_->samples());
    EXPECT_EQ(roadmap_digest(r.roadmaps.roadmap), roadmap_digest(builder_->roadmap()));
    EXPECT_EQ(roadmap_digest(*r.roadmaps.dense), roadmap_digest(*builder_->dense()));
    EXPECT_EQ(r.roadmaps.dense_ids.size(), builder_->dense_ids().size());
  }
  std::vector<std::unique_ptr<planning::Scene>> scenes_;
  std::uint64_t tasks_ = 0;
};

TEST_F(RoadmapStoreTaskTest, ATaskCommitAfterASnapshotOfTheSameSampleCountIsRecoveredAndFolded) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    (void)build_and_commit(*store, 3, 300);
    store->compact();                   // the snapshot holds every sample drawn so far
    add_task(*store, "cracks", 25, 5);  // a commit of no new sample, in the journal after it
  }
  {
    StoreRecovery r;
    auto store = RoadmapStore::open(path, scene_->pois().size(), r);
    ASSERT_EQ(r.tasks.size(), 1u) << "the task's commit was taken for one the snapshot holds";
    EXPECT_EQ(r.tasks[0].name, "cracks");
    EXPECT_EQ(r.roadmaps.roadmap.poi_count(), scene_->pois().size() + 25);
    EXPECT_EQ(r.journal_commits, 1u);
    expect_builders_state(r);
    store->compact();  // now the snapshot holds the task
  }
  StoreRecovery r;
  auto store = RoadmapStore::open(path, scene_->pois().size(), r);
  EXPECT_EQ(r.journal_commits, 0u);
  ASSERT_EQ(r.tasks.size(), 1u);
  EXPECT_EQ(r.tasks[0].pois, sample_task_pois(*scene_, 25, 5));
  expect_builders_state(r);
}

TEST_F(RoadmapStoreTaskTest, TwoTasksBetweenBuildCommitsReplayInOrder) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(2);
    (void)build_and_commit(*store, 2, 300);
    add_task(*store, "one", 10, 1);
    store->wait_for_compaction();
    add_task(*store, "two", 15, 2);
    store->wait_for_compaction();
    const std::uint64_t v = builder_->roadmap().version();
    const std::uint64_t dv = builder_->dense()->version();
    builder_->extend(400);  // later samples see every task's POIs
    store->commit(commit_since(view(*builder_), v, dv));
    store->wait_for_compaction();
  }
  StoreRecovery r;
  auto store = RoadmapStore::open(path, scene_->pois().size(), r);
  ASSERT_EQ(r.tasks.size(), 2u);
  EXPECT_EQ(r.tasks[0].name, "one");
  EXPECT_EQ(r.tasks[1].name, "two");
  expect_builders_state(r);
}

TEST_F(RoadmapStoreTaskTest, ARemovalAfterASnapshotIsRecoveredFoldedAndChangesNoVertex) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    (void)build_and_commit(*store, 2, 300);
    add_task(*store, "one", 10, 1);
    add_task(*store, "two", 15, 2);
    store->compact();        // the snapshot holds both tasks at this sample count
    remove_task(*store, 0);  // in the journal after it, of the same sample count
  }
  for (const int reopening : {0, 1}) {
    StoreRecovery r;
    auto store = RoadmapStore::open(path, scene_->pois().size(), r);
    ASSERT_EQ(r.tasks.size(), 2u) << reopening;
    EXPECT_TRUE(r.tasks[0].removed) << "the removal's commit was taken for one the snapshot holds (" << reopening
                                    << ")";
    EXPECT_FALSE(r.tasks[1].removed);
    EXPECT_EQ(r.journal_commits, reopening == 0 ? 1u : 0u);
    EXPECT_EQ(r.roadmaps.roadmap.poi_count(), scene_->pois().size() + 25) << "a removed task's POIs keep their ids";
    expect_builders_state(r);
    store->compact();  // the snapshot now holds the removal
  }
}

TEST(RoadmapStoreTaskFold, ARemovalOfNoTaskOrOfARemovedOneOrOutOfOrderChangesNothing) {
  std::vector<InspectionTask> tasks;
  BuildCommit add;
  add.tasks = {{"a", {Vec3(0, 0, 0)}}, {"b", {Vec3(1, 1, 1)}}};
  add.task_count = 2;
  fold_tasks(tasks, add);
  ASSERT_EQ(tasks.size(), 2u);
  BuildCommit remove;
  remove.removed_tasks = {1};
  remove.task_count = 3;
  fold_tasks(tasks, remove);
  EXPECT_TRUE(tasks[1].removed);
  EXPECT_EQ(task_events(tasks), 3u);
  const auto before = tasks;
  remove.task_count = 4;
  EXPECT_THROW(fold_tasks(tasks, remove), std::runtime_error) << "removed twice";
  remove.removed_tasks = {2};
  EXPECT_THROW(fold_tasks(tasks, remove), std::runtime_error) << "no task 2";
  remove.removed_tasks = {0};
  remove.task_count = 3;
  EXPECT_THROW(fold_tasks(tasks, remove), std::runtime_error) << "a task count that does not follow";
  ASSERT_EQ(tasks.size(), before.size());
  EXPECT_FALSE(tasks[0].removed);
  EXPECT_TRUE(tasks[1].removed);
  // A removal's commit is ordered by its task events, not its samples.
  remove.task_count = 4;
  EXPECT_FALSE(snapshot_holds(remove, 0, 3));
  EXPECT_TRUE(snapshot_holds(remove, 0, 4));
  // A whole list (a snapshot, a new roadmap's first commit) records its removals.
  BuildCommit whole;
  set_tasks(whole, tasks);
  std::vector<InspectionTask> again;
  fold_tasks(again, decode_commit(encode_commit(whole)));
  ASSERT_EQ(again.size(), 2u);
  EXPECT_FALSE(again[0].removed);
  EXPECT_TRUE(again[1].removed);
  EXPECT_EQ(again[1].pois, tasks[1].pois);
}

TEST(RoadmapStoreTaskCodec, ACommitWithoutTasksEncodesAsBeforeAndATaskRoundTrips) {
  BuildCommit plain;
  plain.samples = 7;
  const std::string before = encode_commit(plain);
  EXPECT_EQ(before.size(), 4 * sizeof(std::uint64_t) + 2 * encode_batch(RoadmapBatch{}).size())
      << "no bytes for tasks when there are none: older stores read as they were";
  BuildCommit with = plain;
  with.tasks = {{"welds", {Vec3(1, 2, 3), Vec3(-4.5, 0.25, 1e-9)}}};
  with.task_count = 3;
  const BuildCommit back = decode_commit(encode_commit(with));
  ASSERT_EQ(back.tasks.size(), 1u);
  EXPECT_EQ(back.tasks[0].name, "welds");
  EXPECT_EQ(back.tasks[0].pois, with.tasks[0].pois);
  EXPECT_EQ(back.task_count, 3u);
  std::string damaged = encode_commit(with);
  damaged.back() ^= 1;  // a POI's last byte: still a commit, another point
  EXPECT_NE(decode_commit(damaged).tasks[0].pois[1], with.tasks[0].pois[1]);
  damaged.resize(damaged.size() - 3);
  EXPECT_THROW((void)decode_commit(damaged), std::runtime_error);
}

}  // namespace
}  // namespace ispars::service
