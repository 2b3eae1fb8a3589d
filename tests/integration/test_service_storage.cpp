// Storage that fails loudly, with real daemons: damage beyond a torn tail is reported with the
// file and the offset, left untouched, and does not stop the daemon serving other scenes.

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "integration/service_fixture.hpp"
#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/sealed_file.hpp"

namespace ispars::test {
namespace {

TEST_F(ServiceTest, ACorruptJournalMiddleFailsItsSceneLoudlyAndTheOthersServe) {
  const std::vector<std::string> no_compaction = {"--compact-every", "100000"};
  std::uint64_t s1_vertices = 0;
  {
    auto daemon = start("d", no_compaction);
    Client c(client_options(domain_));
    for (const char* s : {"s0", "s1"}) {
      c.load(s);
      c.build(s, ispars_build(3000));
      c.wait_idle(s, {}, kLong);
    }
    s1_vertices = c.stats("s1").vertices;
    ASSERT_EQ(daemon->terminate(), 0);
  }
  const auto journal = dir_.path() / "data-d" / "s0" / "journal.log";
  const RecordReplay intact = read_record_file(journal, "ISPJRN03", [](const std::string&) { return std::string(); });
  ASSERT_GE(intact.payloads.size(), 3u) << "the build committed too few chunks for a middle";
  std::string damaged = read_text(journal);
  const std::size_t second = 8 + 16 + intact.payloads[0].size();  // the second commit's header
  damaged[second + 16 + intact.payloads[1].size() / 2] ^= 0x01;
  std::ofstream(journal, std::ios::binary | std::ios::trunc) << damaged;

  auto daemon = start("d", no_compaction);
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state, SceneState::failed);
  EXPECT_NE(s0.last_error.find("journal.log is damaged at byte " + std::to_string(second) + " (commit 2)"),
            std::string::npos)
      << s0.last_error;
  EXPECT_EQ(c.stats("s1").vertices, s1_vertices) << "another scene stopped serving";
  try {
    c.build("s0", ispars_build(1000));
    FAIL() << "a build without replace went over a damaged store";
  } catch (const ClientError& e) {
    EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_text(journal), damaged) << "the damaged journal was changed";
  EXPECT_TRUE(daemon->alive());
}

// As a user reported it: bit 31 of a middle record's length flipped, which pointed the length past
// the end of the file. Before format 03 that read as a torn tail, and the restart cut every commit
// after it and served the rest as idle. Now the header's own checksum names it as damage.
TEST_F(ServiceTest, AFlippedLengthInTheJournalsMiddleFailsTheSceneAndCutsNothing) {
  {
    auto daemon = start("d", {"--compact-every", "100000"});
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(3000));
    ASSERT_EQ(c.wait_idle("s0", {}, kLong).state, SceneState::idle);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  const auto store = dir_.path() / "data-d" / "s0";
  const RecordReplay intact =
      read_record_file(store / "journal.log", "ISPJRN03", [](const std::string&) { return std::string(); });
  ASSERT_GE(intact.payloads.size(), 3u) << "the build committed too few chunks for a middle";
  const std::size_t middle = intact.payloads.size() / 2;
  std::size_t offset = 8;
  for (std::size_t i = 0; i < middle; ++i) offset += 16 + intact.payloads[i].size();
  std::string damaged = read_text(store / "journal.log");
  damaged[offset + 3] ^= static_cast<char>(0x80);  // bit 31 of the length
  std::ofstream(store / "journal.log", std::ios::binary | std::ios::trunc) << damaged;

  auto daemon = start("d");
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state, SceneState::failed);
  EXPECT_NE(s0.last_error.find("journal.log is damaged at byte " + std::to_string(offset) + " (commit " +
                               std::to_string(middle + 1) + "): record header checksum mismatch"),
            std::string::npos)
      << s0.last_error;
  EXPECT_EQ(read_text(store / "journal.log"), damaged) << "the damaged journal was changed";
  EXPECT_FALSE(std::filesystem::exists(store / "journal.log.torn.1")) << "damage was handled as a torn tail";
  EXPECT_TRUE(daemon->alive());
}

// As a user reported it: one bit flipped in the last record (complete, fsync'ed, acknowledged).
// Before head named the durable bytes, the restart cut it aside as a torn write and served the
// roadmap a commit back, idle, with a warning only. Now the scene is FAILED and nothing is cut.
TEST_F(ServiceTest, AFlippedBitInTheLastAcknowledgedCommitFailsTheSceneAndCutsNothing) {
  std::uint64_t acknowledged = 0;
  {
    auto daemon = start("d", {"--compact-every", "100000"});
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(3000));
    acknowledged = c.wait_idle("s0", {}, kLong).samples_done;
    ASSERT_EQ(daemon->terminate(), 0);
  }
  const auto store = dir_.path() / "data-d" / "s0";
  std::string damaged = read_text(store / "journal.log");
  damaged[damaged.size() - 7] ^= 0x20;  // inside the last record's payload
  std::ofstream(store / "journal.log", std::ios::binary | std::ios::trunc) << damaged;

  auto daemon = start("d");
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state, SceneState::failed) << "served at " << s0.samples_done << " of " << acknowledged << " samples";
  EXPECT_NE(s0.last_error.find("record checksum mismatch in an acknowledged commit"), std::string::npos)
      << s0.last_error;
  EXPECT_EQ(read_text(store / "journal.log"), damaged) << "the damaged journal was changed";
  EXPECT_FALSE(std::filesystem::exists(store / "journal.log.torn.1")) << "damage was handled as a torn tail";
  EXPECT_TRUE(daemon->alive());
}

// The scene file was edited between two runs of the daemon (another procedural seed: another
// mesh). The old roadmap is not served as idle, replayed or extended: the scene is FAILED naming
// the change, its files stay, and a build with replace rebuilds it.
TEST_F(ServiceTest, AnEditedSceneFailsItsStoredRoadmapUntilRebuilt) {
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(1500));
    c.wait_idle("s0", {}, kLong);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  std::ofstream(scene_dir_ / "s0.yaml") << "procedural: {kind: tank_tower, seed: 77}\n";
  const auto recipe = dir_.path() / "data-d" / "s0" / "recipe.json";
  const std::string recipe_before = read_text(recipe);
  auto daemon = start("d");
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state, SceneState::failed);
  EXPECT_NE(s0.last_error.find("was built on another version of the scene"), std::string::npos) << s0.last_error;
  EXPECT_EQ(s0.vertices, 0u);
  EXPECT_THROW(c.extend("s0", 500), ClientError);
  EXPECT_EQ(read_text(recipe), recipe_before);
  c.build("s0", ispars_build(1500, 1, true));
  const auto rebuilt = c.wait_idle("s0", {}, kLong);
  EXPECT_EQ(rebuilt.state, SceneState::idle) << rebuilt.last_error;
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 1500, 1));
}

// IRIS-C's first extend after a restart replays the recipe (the other methods resume from their
// stored roadmaps) and compares the result with the stored roadmap byte for byte. A stored recipe
// that does not give the stored roadmap (here its seed edited on disk) is reported by name, the
// scene keeps serving what is stored, and no file is rewritten.
TEST_F(ServiceTest, AReplayThatDoesNotReproduceTheStoredRoadmapFailsByNameAndRewritesNothing) {
  std::uint64_t digest = 0;
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    BuildArgs irisc = ispars_build(1500, 7);
    irisc.method = BuildMethod::irisc;
    c.build("s0", irisc);
    c.wait_idle("s0", {}, kLong);
    digest = roadmap_digest(c.snapshot("s0").roadmap);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  // A recipe that does not give its roadmap, yet passes its own checksum (as a builder's bug would
  // leave it): the seed changed and the file sealed again.
  const auto store = dir_.path() / "data-d" / "s0";
  nlohmann::json recipe = nlohmann::json::parse(read_text(store / "recipe.json"));
  ASSERT_EQ(recipe.at("seed"), 7) << recipe;
  recipe["seed"] = 8;
  std::ofstream(store / "recipe.json", std::ios::trunc) << seal_json(recipe).dump(2) << "\n";
  std::map<std::string, std::string> files;
  for (const auto& f : std::filesystem::directory_iterator(store)) files[f.path().filename()] = read_text(f.path());

  auto daemon = start("d");
  Client c(client_options(domain_));
  EXPECT_EQ(c.stats("s0").state, SceneState::idle) << "served as stored until something replays it";
  c.extend("s0", 500);
  const SceneStatus failed = c.wait_idle("s0", {}, kLong);
  EXPECT_EQ(failed.state, SceneState::failed);
  EXPECT_NE(failed.last_error.find("replaying the recipe to 1500 samples did not reproduce the stored roadmap"),
            std::string::npos)
      << failed.last_error;
  EXPECT_EQ(failed.samples_done, 1500u);
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), digest) << "what is stored is still served";
  for (const auto& [name, bytes] : files) EXPECT_EQ(read_text(store / name), bytes) << name << " was rewritten";
  EXPECT_TRUE(daemon->alive());
}

// As a user reported it: one bit of recipe.json flipped turned seed 3 into seed 2, with no
// warning, a clean verify, and a next extend that diverged. Now the recipe's checksum fails: the
// scene is FAILED naming the file, nothing is rewritten, and a build with replace recovers it.
TEST_F(ServiceTest, AFlippedBitInTheRecipeFailsTheSceneByName) {
  {
    auto daemon = start("d");
    Client c(client_options(domain_));
    c.load("s0");
    c.build("s0", ispars_build(1500, 3));
    c.wait_idle("s0", {}, kLong);
    ASSERT_EQ(daemon->terminate(), 0);
  }
  const auto store = dir_.path() / "data-d" / "s0";
  std::string recipe = read_text(store / "recipe.json");
  const auto at = recipe.find("\"seed\": 3");
  ASSERT_NE(at, std::string::npos) << recipe;
  recipe[at + std::string("\"seed\": ").size()] ^= 0x01;  // '3' -> '2'
  std::ofstream(store / "recipe.json", std::ios::binary | std::ios::trunc) << recipe;
  std::map<std::string, std::string> files;
  for (const auto& f : std::filesystem::directory_iterator(store)) files[f.path().filename()] = read_text(f.path());

  auto daemon = start("d");
  Client c(client_options(domain_));
  const auto s0 = c.stats("s0");
  EXPECT_EQ(s0.state, SceneState::failed) << "served with seed " << s0.seed;
  EXPECT_NE(s0.last_error.find("recipe.json fails its checksum"), std::string::npos) << s0.last_error;
  EXPECT_THROW(c.extend("s0", 500), ClientError);
  for (const auto& [name, bytes] : files) EXPECT_EQ(read_text(store / name), bytes) << name << " was rewritten";
  c.build("s0", ispars_build(1500, 3, true));
  EXPECT_EQ(c.wait_idle("s0", {}, kLong).state, SceneState::idle);
  EXPECT_EQ(roadmap_digest(c.snapshot("s0").roadmap), reference_digest(scene_dir_ / "s0.yaml", 1500, 3));
  EXPECT_TRUE(daemon->alive());
}

}  // namespace
}  // namespace ispars::test
