// ChangeLedger: change requests begun and answered survive a restart, a power cut loses at most
// an answer (never a begun request), damage is named and kept, and the file stays bounded.

#include <gtest/gtest.h>

#include <fstream>

#include "ispars/service/change_ledger.hpp"
#include "support/power_cut_fs.hpp"
#include "support/test_support.hpp"

namespace ispars::service {
namespace {

using test::PowerCut;
using test::PowerCutFileSystem;

LedgerAnswer ok(const std::string& message) { return {true, "", message}; }

void write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

TEST(ChangeLedger, ARequestBegunAndAnsweredIsFoundAfterARestart) {
  test::TempDir dir;
  {
    ChangeLedger ledger(dir.path());
    EXPECT_EQ(ledger.from_before("c1", 7), std::nullopt) << "nothing from before in a new file";
    ledger.begin("c1", 7, "EXTEND", "x");
    ledger.answer("c1", 7, ok("extending 'x' by 5000 samples"));
    ledger.begin("c1", 8, "DROP", "x");  // the daemon stops before answering it
    EXPECT_EQ(ledger.from_before("c1", 7), std::nullopt) << "this run's requests are the reply cache's";
  }
  ChangeLedger again(dir.path());
  const auto answered = again.from_before("c1", 7);
  ASSERT_TRUE(answered.has_value());
  EXPECT_EQ(answered->operation, "EXTEND");
  EXPECT_EQ(answered->scene, "x");
  ASSERT_TRUE(answered->answer.has_value());
  EXPECT_TRUE(answered->answer->ok);
  EXPECT_EQ(answered->answer->message, "extending 'x' by 5000 samples");
  const auto interrupted = again.from_before("c1", 8);
  ASSERT_TRUE(interrupted.has_value());
  EXPECT_FALSE(interrupted->answer.has_value()) << "begun, never answered: the retry is told so";
  EXPECT_EQ(again.from_before("c2", 7), std::nullopt) << "another client's 7 is another request";
  EXPECT_TRUE(again.damage().empty());
}

TEST(ChangeLedger, APowerCutLosesAnAnswerButNeverABegunRequest) {
  int torn = 0;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    PowerCutFileSystem fs;
    fs.create_directories("/d");
    fs.sync_directory("/");
    {
      ChangeLedger ledger("/d", fs);
      ledger.begin("c", 1, "EXTEND", "x");
      ledger.answer("c", 1, ok("done"));
      ledger.begin("c", 2, "EXTEND", "x");
      ledger.answer("c", 2, ok("unsynced, torn"));
      fs.cut_at(1);
      EXPECT_THROW(ledger.begin("c", 3, "EXTEND", "x"), PowerCut);
    }
    fs.power_on(seed);
    ChangeLedger after("/d", fs);
    ASSERT_TRUE(after.from_before("c", 1).has_value()) << seed;
    ASSERT_TRUE(after.from_before("c", 2).has_value()) << "its begin was fsync'ed before the change: " << seed;
    EXPECT_EQ(after.from_before("c", 3), std::nullopt) << "never durably begun: never made";
    EXPECT_TRUE(after.damage().empty()) << "a torn last line is not damage: " << after.damage().front();
    torn += after.torn_tail();
    after.begin("c", 4, "EXTEND", "x");  // starts its own line after a torn one
    ChangeLedger third("/d", fs);
    EXPECT_TRUE(third.from_before("c", 4).has_value()) << seed;
    EXPECT_TRUE(third.damage().empty()) << seed;
  }
  EXPECT_GT(torn, 0) << "no seed tore the unsynced answer: the case is not exercised";
}

TEST(ChangeLedger, ADamagedRecordIsNamedSkippedAndKeptAsItIs) {
  test::TempDir dir;
  {
    ChangeLedger ledger(dir.path());
    for (std::uint64_t seq = 1; seq <= 3; ++seq) {
      ledger.begin("c", seq, "BUILD", "x");
      ledger.answer("c", seq, ok("building"));
    }
  }
  const auto path = dir.path() / ".changes.log";
  std::string text = test::read_text(path);
  const std::size_t second = text.find('\n') + 1;  // the first answer record
  text[second + 5] ^= 0x01;
  write_bytes(path, text);
  ChangeLedger ledger(dir.path());
  ASSERT_EQ(ledger.damage().size(), 1u);
  EXPECT_NE(ledger.damage()[0].find("record at byte " + std::to_string(second)), std::string::npos)
      << ledger.damage()[0];
  ASSERT_TRUE(ledger.from_before("c", 1).has_value());
  EXPECT_FALSE(ledger.from_before("c", 1)->answer.has_value()) << "its answer is not believed";
  EXPECT_TRUE(ledger.from_before("c", 3)->answer.has_value());
  EXPECT_EQ(test::read_text(path), text) << "opening changed nothing";
}

TEST(ChangeLedger, TheFileIsRewrittenToItsNewestRequestsAndDamageIsKeptAside) {
  test::TempDir dir;
  {
    ChangeLedger ledger(dir.path(), disk(), 4);
    ledger.begin("c", 1, "BUILD", "x");
  }
  std::string text = test::read_text(dir.path() / ".changes.log");
  text[3] ^= 0x01;
  write_bytes(dir.path() / ".changes.log", text + "\n");
  {
    ChangeLedger ledger(dir.path(), disk(), 4);
    ASSERT_EQ(ledger.damage().size(), 1u);
    for (std::uint64_t seq = 2; seq <= 40; ++seq) {
      ledger.begin("c", seq, "EXTEND", "x");
      ledger.answer("c", seq, ok("extending"));
    }
  }
  EXPECT_EQ(test::read_text(dir.path() / ".changes.log.damaged").substr(0, text.size()), text)
      << "the damaged file was kept before the rewrite";
  ChangeLedger reopened(dir.path(), disk(), 4);
  EXPECT_TRUE(reopened.damage().empty());
  for (std::uint64_t seq = 37; seq <= 40; ++seq) EXPECT_TRUE(reopened.from_before("c", seq).has_value()) << seq;
  EXPECT_LE(reopened.recovered(), 4u * 4u) << "bounded: rewritten at four times its keep";
}

}  // namespace
}  // namespace ispars::service
