// The roadmap store's compaction off the build thread: every crash window recovers the last
// commit, a damaged rotated journal is named and left as it was, and the fold of the files is the
// snapshot of the live roadmaps byte for byte.

#include "roadmap_store_fixture.hpp"

namespace ispars::service {
namespace {

// Compaction runs off the build thread: the journal is renamed journal.old, and a thread folds
// snapshot.bin and journal.old into a new snapshot. Every moment a crash can stop that at leaves
// files that recover the last commit; the next open finishes the fold, to the same bytes.
TEST_F(RoadmapStoreTest, EveryCrashWindowOfABackgroundCompactionRecoversTheLastCommit) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  std::string s1, s2, j_a, j_b;  // snapshots after 3 and 6 commits; journals of 4-6 and 7-8
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    planning::BuildOptions options;
    options.seed = recipe_.seed;
    builder_ = planning::make_roadmap_builder(BuildMethod::ispars, *scene_, options);
    std::uint64_t v = 0, dv = 0;
    for (int i = 0; i < 8; ++i) {
      if (i > 0) builder_->extend(150);
      store->commit(commit_since(view(*builder_), v, dv));
      v = builder_->roadmap().version();
      dv = builder_->dense()->version();
      states.push_back({builder_->samples(), roadmap_digest(builder_->roadmap()), roadmap_digest(*builder_->dense()),
                        builder_->dense_ids().size()});
      if (i == 2 || i == 5) {
        if (i == 5) j_a = slurp(path / "journal.log");
        store->compact();
        EXPECT_FALSE(std::filesystem::exists(path / "journal.old"));
        (i == 2 ? s1 : s2) = slurp(path / "snapshot.bin");
        // The fold of the files is the snapshot of the live roadmaps, byte for byte.
        const RecordReplay snapshot =
            read_record_file(path / "snapshot.bin", "ISPSNP03", [](const std::string&) { return std::string(); });
        ASSERT_EQ(snapshot.payloads.size(), 1u);
        EXPECT_EQ(snapshot.payloads[0], encode_commit(commit_since(view(*builder_), 0, 0))) << "after commit " << i + 1;
      }
    }
    j_b = slurp(path / "journal.log");
  }
  const auto set_files = [&](const std::string& snapshot, const std::string* old, const std::string* journal) {
    spit(path / "snapshot.bin", snapshot);
    std::filesystem::remove(path / "journal.old");
    std::filesystem::remove(path / "journal.log");
    if (old) spit(path / "journal.old", *old);
    if (journal) spit(path / "journal.log", *journal);
  };
  const auto recovers = [&](const Committed& expected, const char* window) {
    SCOPED_TRACE(window);
    StoreRecovery r;
    auto store = RoadmapStore::open(path, scene_->pois().size(), r);
    expect_state(r, expected);
    store->wait_for_compaction();  // open() finished the interrupted fold
    EXPECT_FALSE(std::filesystem::exists(path / "journal.old"));
    EXPECT_EQ(slurp(path / "snapshot.bin"), s2) << "the finished fold differs from the uninterrupted one";
    store.reset();
    StoreRecovery again;
    (void)RoadmapStore::open(path, scene_->pois().size(), again);
    expect_state(again, expected);
  };
  set_files(s1, &j_a, nullptr);
  recovers(states[5], "renamed to journal.old, no new journal.log yet");
  set_files(s1, &j_a, &j_b);
  recovers(states[7], "folding, with commits after the rotation");
  set_files(s2, &j_a, &j_b);
  recovers(states[7], "the new snapshot in place, journal.old not yet removed");

  // A rotated journal was whole: a flipped byte or a cut in it is damage, named, and left as is.
  for (const bool cut : {false, true}) {
    std::string damaged = j_a;
    if (cut)
      damaged.resize(damaged.size() - 5);
    else
      damaged[damaged.size() / 2] ^= 0x04;
    set_files(s1, &damaged, &j_b);
    StoreRecovery r;
    try {
      (void)RoadmapStore::open(path, scene_->pois().size(), r);
      FAIL() << "a damaged journal.old was opened";
    } catch (const StoreDamage& e) {
      EXPECT_NE(std::string(e.what()).find("journal.old is damaged at byte"), std::string::npos) << e.what();
    }
    EXPECT_EQ(slurp(path / "journal.old"), damaged);
    EXPECT_EQ(slurp(path / "snapshot.bin"), s1);
    EXPECT_EQ(slurp(path / "journal.log"), j_b);
  }
}

}  // namespace
}  // namespace ispars::service
