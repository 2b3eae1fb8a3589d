// The roadmap store: commits survive reopening, a crash at any byte recovers a committed state,
// compaction's crash window is harmless, and bad commits change nothing.

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include "roadmap_store_fixture.hpp"

namespace ispars::service {
namespace {

TEST_F(RoadmapStoreTest, ReopeningRecoversTheLastCommitThroughSnapshotsAndJournal) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(3);
    states = build_and_commit(*store, 8, 200);
  }
  EXPECT_TRUE(std::filesystem::exists(path / "snapshot.bin"));
  StoreRecovery r;
  auto store = RoadmapStore::open(path, scene_->pois().size(), r);
  EXPECT_EQ(r.recipe.seed, 11u);
  EXPECT_EQ(r.recipe.generation, 42u);
  EXPECT_FALSE(r.torn_tail);
  EXPECT_EQ(r.journal_commits, 8u % 3u);
  expect_state(r, states.back());
  EXPECT_EQ(test::fingerprint(r.roadmaps.roadmap), test::fingerprint(builder_->roadmap()));
  EXPECT_TRUE(std::equal(r.roadmaps.dense_ids.begin(), r.roadmaps.dense_ids.end(), builder_->dense_ids().begin(),
                         builder_->dense_ids().end()));
  // Over a store, a new one is made aside: it takes the place at its first commit, not before.
  EXPECT_NE(RoadmapStore::create(path, recipe_)->dir(), path);
}

TEST_F(RoadmapStoreTest, ACrashAtAnyByteOfTheJournalRecoversACommittedState) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    states = build_and_commit(*store, 5, 150);
  }
  const std::string journal = slurp(path / "journal.log");
  // Cut at 300 points spread over the file (the journal holds no snapshot here).
  for (std::size_t k = 0; k <= 300; ++k) {
    const std::size_t cut = journal.size() * k / 300;
    spit(path / "journal.log", journal.substr(0, cut));
    StoreRecovery r;
    auto store = RoadmapStore::open(path, scene_->pois().size(), r);
    const std::size_t commits = r.journal_commits;
    ASSERT_LE(commits, states.size());
    if (commits == 0) {
      EXPECT_EQ(r.roadmaps.roadmap.version(), 0u);
    } else {
      expect_state(r, states[commits - 1]);
    }
  }
}

// A flipped bit in commit 4 of 6 is not a torn tail: opening refuses, names the file and the
// offset, and leaves every byte as it was (before, the journal was cut to 3 commits).
TEST_F(RoadmapStoreTest, ACorruptCommitInTheMiddleIsReportedAndNothingIsCut) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    (void)build_and_commit(*store, 6, 150);
  }
  std::string journal = slurp(path / "journal.log");
  const RecordReplay intact =
      read_record_file(path / "journal.log", "ISPJRN03", [](const std::string&) { return std::string(); });
  ASSERT_EQ(intact.payloads.size(), 6u);
  std::size_t offset = 8;  // the magic, then records of 16 header bytes and a payload each
  for (int i = 0; i < 3; ++i) offset += 16 + intact.payloads[static_cast<std::size_t>(i)].size();
  journal[offset + 16 + intact.payloads[3].size() / 2] ^= 0x10;
  spit(path / "journal.log", journal);
  StoreRecovery r;
  try {
    (void)RoadmapStore::open(path, scene_->pois().size(), r);
    FAIL() << "a corrupt middle was opened";
  } catch (const StoreDamage& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("journal.log is damaged at byte " + std::to_string(offset) + " (commit 4)"), std::string::npos)
        << what;
    EXPECT_NE(what.find("record checksum mismatch"), std::string::npos) << what;
  }
  EXPECT_EQ(slurp(path / "journal.log"), journal) << "the damaged journal was rewritten";
  // Every bit of commit 4's length field flipped, one at a time: each is damage named the same
  // way, never a torn tail to cut (before format 03, a length sent past the end of the file cut
  // commits 4 to 6).
  journal[offset + 16 + intact.payloads[3].size() / 2] ^= 0x10;
  for (int bit = 0; bit < 64; ++bit) {
    std::string flipped = journal;
    flipped[offset + static_cast<std::size_t>(bit / 8)] ^= static_cast<char>(1u << (bit % 8));
    spit(path / "journal.log", flipped);
    try {
      (void)RoadmapStore::open(path, scene_->pois().size(), r);
      ADD_FAILURE() << "bit " << bit << " of commit 4's length flipped, and the store opened";
    } catch (const StoreDamage& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("journal.log is damaged at byte " + std::to_string(offset) + " (commit 4)"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("record header checksum mismatch"), std::string::npos) << what;
    }
    ASSERT_EQ(slurp(path / "journal.log"), flipped) << "bit " << bit << ": the damaged journal was rewritten";
  }
  for (const auto& entry : std::filesystem::directory_iterator(path)) {
    EXPECT_EQ(entry.path().filename().string().find("torn"), std::string::npos) << entry.path();
  }
  // A damaged snapshot is refused the same way.
  write_file_atomically(path / "snapshot.bin", "ISPSNP01 and then garbage");
  EXPECT_THROW((void)RoadmapStore::open(path, scene_->pois().size(), r), StoreDamage);
}

// A flipped bit in the last commit, acknowledged (head names the bytes durable after it), is
// damage: opening refuses and nothing is cut (before, it was cut aside as a torn write and the
// roadmap went back a commit). A record torn after it (a crash mid-append, before head moved)
// is still a tear, and so is the same flip in a store whose head predates the field.
TEST_F(RoadmapStoreTest, AFlippedBitInTheLastAcknowledgedCommitIsDamageNotATear) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    states = build_and_commit(*store, 4, 150);
  }
  const std::string journal = slurp(path / "journal.log");
  const auto head = read_store_head(path);
  ASSERT_TRUE(head.has_value());
  EXPECT_EQ(head->journal_bytes, journal.size());
  std::string flipped = journal;
  flipped[journal.size() - 5] ^= 0x04;  // inside the last record's payload
  spit(path / "journal.log", flipped);
  StoreRecovery r;
  try {
    (void)RoadmapStore::open(path, scene_->pois().size(), r);
    FAIL() << "an acknowledged commit with a flipped bit was cut as a torn tail";
  } catch (const StoreDamage& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("(commit 4): record checksum mismatch in an acknowledged commit"), std::string::npos) << what;
  }
  EXPECT_EQ(slurp(path / "journal.log"), flipped) << "the damaged journal was rewritten";
  EXPECT_EQ(read_store_head(path)->journal_bytes, journal.size()) << "head was rewritten";
  // A crash mid-append: the intact journal and half a record after it; head not moved yet.
  spit(path / "journal.log", journal + flipped.substr(8, 40));
  {
    StoreRecovery torn;
    auto store = RoadmapStore::open(path, scene_->pois().size(), torn);
    EXPECT_TRUE(torn.torn_tail);
    expect_state(torn, states.back());
  }
  EXPECT_EQ(slurp(path / "journal.log"), journal) << "the torn half record was not cut";
  // A head without the field (written before it existed): the flip reads as a tear, as before.
  spit(path / "journal.log", flipped);
  spit(path / "head", fmt::format("{} {}\n", head->generation, head->samples));
  StoreRecovery legacy;
  (void)RoadmapStore::open(path, scene_->pois().size(), legacy);
  EXPECT_TRUE(legacy.torn_tail);
  expect_state(legacy, states[2]);
}

// One bit flipped in the journal's magic: damage named with the file and byte 0, nothing touched
// (before, a plain error that kept the scene from loading at all, and takeovers failed on it).
TEST_F(RoadmapStoreTest, AFlippedBitInTheMagicIsDamageAtByteZero) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    (void)build_and_commit(*store, 2, 150);
  }
  std::string journal = slurp(path / "journal.log");
  journal[3] ^= 0x02;
  spit(path / "journal.log", journal);
  StoreRecovery r;
  try {
    (void)RoadmapStore::open(path, scene_->pois().size(), r);
    FAIL() << "a journal with a bad magic was opened";
  } catch (const StoreDamage& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("is damaged at byte 0"), std::string::npos) << what;
    EXPECT_NE(what.find("journal.log is not a ISPJRN03 file (bad magic)"), std::string::npos) << what;
  }
  EXPECT_THROW((void)RoadmapStore::read(path, scene_->pois().size()), StoreDamage);
  EXPECT_EQ(slurp(path / "journal.log"), journal);
}

TEST_F(RoadmapStoreTest, ACrashBetweenSnapshotAndJournalResetLosesNothingAndDuplicatesNothing) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  std::string journal_before_compaction;
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    states = build_and_commit(*store, 4, 200);
    journal_before_compaction = slurp(path / "journal.log");
    store->compact();
  }
  // As if the process died after renaming the snapshot into place but before the new journal.
  spit(path / "journal.log", journal_before_compaction);
  StoreRecovery r;
  auto store = RoadmapStore::open(path, scene_->pois().size(), r);
  expect_state(r, states.back());
  EXPECT_EQ(r.journal_commits, 0u);
}

TEST_F(RoadmapStoreTest, ACommitThatDoesNotContinueIsRefusedAndChangesNothing) {
  const auto path = dir_.path() / "bridge";
  auto store = RoadmapStore::create(path, recipe_);
  build_and_commit(*store, 2, 200);
  planning::BuiltRoadmaps recovered;
  {
    StoreRecovery r;
    store.reset();
    store = RoadmapStore::open(path, scene_->pois().size(), r);
    recovered = std::move(r.roadmaps);
  }
  const std::uint64_t before = roadmap_digest(recovered.roadmap);
  BuildCommit stale = commit_since(view(*builder_), 0, 0);  // starts at version 0 again
  EXPECT_THROW(apply_commit(recovered, stale), std::runtime_error);
  EXPECT_EQ(roadmap_digest(recovered.roadmap), before);
  BuildCommit wrong_ids = commit_since(view(*builder_), 0, 0);
  wrong_ids.new_dense_ids.pop_back();
  planning::BuiltRoadmaps fresh{0, Roadmap(scene_->pois().size()), Roadmap(scene_->pois().size()), {}};
  EXPECT_THROW(apply_commit(fresh, wrong_ids), std::runtime_error);
  EXPECT_EQ(fresh.roadmap.version(), 0u);
}

TEST_F(RoadmapStoreTest, RecipesRoundTripAndBadOnesAreNamed) {
  const RoadmapRecipe back = recipe_from_json(recipe_to_json(recipe_));
  EXPECT_EQ(back.scene, recipe_.scene);
  EXPECT_EQ(back.method, recipe_.method);
  EXPECT_EQ(back.seed, recipe_.seed);
  EXPECT_EQ(back.dense_delta, recipe_.dense_delta);
  EXPECT_EQ(back.generation, recipe_.generation);
  EXPECT_EQ(back.variant, recipe_.variant);
  RoadmapRecipe paper = recipe_;
  paper.variant = SparsVariant::alg1;
  EXPECT_EQ(recipe_from_json(recipe_to_json(paper)).variant, SparsVariant::alg1);
  // A sealed recipe with one value changed fails its checksum; re-indented, it does not.
  nlohmann::json sealed = nlohmann::json::parse(recipe_to_json(recipe_));
  ASSERT_TRUE(sealed.contains("crc32"));
  EXPECT_EQ(recipe_from_json(sealed.dump()).seed, recipe_.seed) << "the seal depends on the indentation";
  sealed["seed"] = recipe_.seed + 1;
  try {
    (void)recipe_from_json(sealed.dump(2));
    FAIL() << "a changed seed passed the seal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("recipe.json fails its checksum"), std::string::npos) << e.what();
  }
  // A recipe written before the variants (and the seal) existed was built with Alg. 1's rules.
  nlohmann::json old = nlohmann::json::parse(recipe_to_json(recipe_));
  old.erase("crc32");
  old.erase("variant");
  EXPECT_EQ(recipe_from_json(old.dump()).variant, SparsVariant::alg1);
  old["variant"] = "greedy";
  EXPECT_THROW((void)recipe_from_json(old.dump()), std::runtime_error);
  EXPECT_THROW((void)recipe_from_json("{"), std::runtime_error);
  try {
    (void)recipe_from_json(R"({"scene": "x"})");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lacks method"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)recipe_from_json(R"({"scene": "x", "method": "prm"})"), std::runtime_error);
}

TEST_F(RoadmapStoreTest, DroppingRemovesTheStoreAndLeftoversAreCleanedAtStart) {
  const auto path = dir_.path() / "bridge";
  RoadmapStore::create(path, recipe_).reset();
  drop_store(path);
  EXPECT_FALSE(std::filesystem::exists(path));
  std::filesystem::create_directories(dir_.path() / ".dropped-other");
  std::filesystem::create_directories(dir_.path() / ".new-third");
  std::filesystem::create_directories(dir_.path() / "kept");
  std::filesystem::create_directories(dir_.path() / "scene.new");  // a scene may be named so
  remove_dropped_stores(dir_.path());
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / ".dropped-other"));
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / ".new-third"));
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "kept"));
  EXPECT_TRUE(std::filesystem::exists(dir_.path() / "scene.new"));
}

TEST_F(RoadmapStoreTest, AnUnloadMarkIsDurableAndRemovable) {
  const auto path = dir_.path() / "bridge";
  { auto store = RoadmapStore::create(path, recipe_); }
  EXPECT_FALSE(marked_unloaded(path));
  mark_unloaded(path, true);
  EXPECT_TRUE(marked_unloaded(path));
  StoreRecovery r;
  { auto store = RoadmapStore::open(path, scene_->pois().size(), r); }  // the mark does not disturb the store
  mark_unloaded(path, false);
  EXPECT_FALSE(marked_unloaded(path));
  mark_unloaded(path, false);  // unmarking twice is harmless
  EXPECT_FALSE(marked_unloaded(path));
}

// read() recovers what open() would, without the writer's lock and without changing a byte:
// what a session serves when its store cannot be written.
TEST_F(RoadmapStoreTest, ReadingAStoreRecoversItsLastCommitAndChangesNothing) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> states;
  auto writer = RoadmapStore::create(path, recipe_);
  writer->set_compact_every(3);
  states = build_and_commit(*writer, 7, 150);
  const std::string journal = test::read_text(path / "journal.log");
  const StoreRecovery read = RoadmapStore::read(path, scene_->pois().size());  // the writer still holds it
  expect_state(read, states.back());
  EXPECT_EQ(read.recipe.seed, 11u);
  EXPECT_EQ(test::read_text(path / "journal.log"), journal);
  writer.reset();
  StoreRecovery opened;
  (void)RoadmapStore::open(path, scene_->pois().size(), opened);
  EXPECT_EQ(test::fingerprint(read.roadmaps.roadmap), test::fingerprint(opened.roadmaps.roadmap));
}

TEST_F(RoadmapStoreTest, ASecondWriterCannotOpenAStoreInUse) {
  const auto path = dir_.path() / "bridge";
  auto first = RoadmapStore::create(path, recipe_);
  StoreRecovery r;
  EXPECT_THROW((void)RoadmapStore::open(path, scene_->pois().size(), r), std::runtime_error);
  first.reset();
  EXPECT_NO_THROW((void)RoadmapStore::open(path, scene_->pois().size(), r));
}

TEST_F(RoadmapStoreTest, CommitsThatLeaveTheSparseRoadmapUnchangedSurviveACompactionAndReopen) {
  // Late in a build most chunks add only dense vertices; after a compaction such commits must
  // not be mistaken for ones the snapshot holds.
  const auto path = dir_.path() / "bridge";
  std::uint64_t samples = 0, dense_digest = 0;
  {
    auto store = RoadmapStore::create(path, recipe_);
    store->set_compact_every(1000);
    build_and_commit(*store, 3, 300);
    store->compact();
    std::uint64_t v = builder_->roadmap().version(), dv = builder_->dense()->version();
    for (int i = 0; i < 40; ++i) {
      builder_->extend(5);
      const BuildCommit c = commit_since(view(*builder_), v, dv);
      store->commit(c);
      v = builder_->roadmap().version();
      dv = builder_->dense()->version();
    }
    samples = builder_->samples();
    dense_digest = roadmap_digest(*builder_->dense());
  }
  StoreRecovery r;
  auto store = RoadmapStore::open(path, scene_->pois().size(), r);
  EXPECT_FALSE(r.torn_tail) << r.tail_problem;
  EXPECT_EQ(r.journal_commits, 40u);
  EXPECT_EQ(r.roadmaps.samples, samples);
  EXPECT_EQ(roadmap_digest(*r.roadmaps.dense), dense_digest);
}

}  // namespace
}  // namespace ispars::service

namespace ispars::service {
namespace {

TEST_F(RoadmapStoreTest, AReplacingStoreLeavesTheOldOneWholeUntilItsFirstCommit) {
  const auto path = dir_.path() / "bridge";
  std::vector<Committed> old_states;
  {
    auto store = RoadmapStore::create(path, recipe_);
    old_states = build_and_commit(*store, 3, 40);
  }
  const std::string old_journal = slurp(path / "journal.log");
  RoadmapRecipe next = recipe_;
  next.seed = 12;
  next.generation = 43;
  {
    auto replacing = RoadmapStore::create(path, next);  // a crash now: the old store as it was
    EXPECT_EQ(slurp(path / "journal.log"), old_journal);
    EXPECT_EQ(RoadmapStore::read_recipe(path).generation, 42u);
  }
  remove_dropped_stores(dir_.path());  // the next start: the staging store that never took its place goes
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / ".new-bridge"));
  StoreRecovery still;
  (void)RoadmapStore::open(path, scene_->pois().size(), still);
  expect_state(still, old_states.back());

  auto replacing = RoadmapStore::create(path, next);
  recipe_ = next;
  const auto new_states = build_and_commit(*replacing, 1, 40);  // its first commit: now it is the store
  EXPECT_EQ(replacing->dir(), path);
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / ".new-bridge"));
  EXPECT_EQ(RoadmapStore::read_recipe(path).generation, 43u);
  replacing.reset();
  StoreRecovery now;
  (void)RoadmapStore::open(path, scene_->pois().size(), now);
  expect_state(now, new_states.back());
}

TEST_F(RoadmapStoreTest, AReplacementCaughtBetweenTheFallbackRenamesIsPutInPlaceAtStart) {
  // What the fallback (no RENAME_EXCHANGE) leaves after a crash between its two renames: the new
  // store, with its first commit, under its staging name, and no store under the scene's name.
  const auto staging = dir_.path() / ".new-bridge";
  std::vector<Committed> states;
  {
    auto store = RoadmapStore::create(staging, recipe_);
    states = build_and_commit(*store, 1, 40);
  }
  remove_dropped_stores(dir_.path());
  EXPECT_FALSE(std::filesystem::exists(staging));
  StoreRecovery r;
  (void)RoadmapStore::open(dir_.path() / "bridge", scene_->pois().size(), r);
  expect_state(r, states.back());
  // A staging store without a commit is only removed.
  { auto empty = RoadmapStore::create(dir_.path() / ".new-other", recipe_); }
  remove_dropped_stores(dir_.path());
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / ".new-other"));
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "other"));
}

}  // namespace
}  // namespace ispars::service
