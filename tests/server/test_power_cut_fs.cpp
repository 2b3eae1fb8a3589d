// The power-cut file system the store's campaign runs on: what it keeps is what was made durable,
// no more and no less, so that the campaign tests the store and not the stand-in.

#include <gtest/gtest.h>

#include "support/power_cut_fs.hpp"

namespace ispars::test {
namespace {

TEST(PowerCutFileSystem, UnsyncedBytesAreLostAndSyncedOnesKept) {
  PowerCutFileSystem fs;
  fs.create_directories("/d");
  fs.sync_directory("/");
  auto f = fs.open("/d/f", FileSystem::Open::existing_or_new);
  fs.sync_directory("/d");
  f->append("kept");
  f->sync();
  f->append(" lost");
  EXPECT_EQ(fs.read("/d/f"), "kept lost");
  fs.cut_at(1);
  EXPECT_THROW(f->append("!"), PowerCut);
  EXPECT_THROW((void)fs.read("/d/f"), PowerCut) << "a machine without power answers nothing";
  fs.power_on();
  EXPECT_EQ(fs.read("/d/f"), "kept");
}

TEST(PowerCutFileSystem, ATornCutKeepsAPrefixOfTheUnsyncedAppendOnly) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    PowerCutFileSystem fs;
    fs.create_directories("/d");
    fs.sync_directory("/");
    auto f = fs.open("/d/f", FileSystem::Open::existing_or_new);
    fs.sync_directory("/d");
    f->append("durable;");
    f->sync();
    f->append("0123456789");
    fs.cut_at(1);
    EXPECT_THROW(f->sync(), PowerCut);
    fs.power_on(seed);
    const std::string after = *fs.read("/d/f");
    EXPECT_EQ(after.substr(0, 8), "durable;");
    EXPECT_EQ(std::string("durable;0123456789").substr(0, after.size()), after) << "seed " << seed;
  }
}

TEST(PowerCutFileSystem, NamesAreDurableOnlyWhenTheirDirectoryIsSynced) {
  PowerCutFileSystem fs;
  fs.create_directories("/d");
  fs.sync_directory("/");
  {
    auto f = fs.open("/d/a", FileSystem::Open::existing_or_new);
    f->append("a");
    f->sync();
  }
  fs.sync_directory("/d");
  {
    auto t = fs.open("/d/b.tmp", FileSystem::Open::truncated);
    t->append("b");
    t->sync();
  }
  fs.rename("/d/b.tmp", "/d/b");   // not yet durable
  EXPECT_TRUE(fs.remove("/d/a"));  // nor this
  fs.create_directories("/d/sub");
  fs.power_on();
  EXPECT_EQ(fs.list("/d"), std::vector<std::string>{"a"}) << "an unsynced rename, removal or creation stayed";
  EXPECT_EQ(fs.read("/d/a"), "a");

  fs.rename("/d/a", "/d/c");
  fs.sync_directory("/d");
  fs.power_on();
  EXPECT_EQ(fs.list("/d"), std::vector<std::string>{"c"});
  EXPECT_EQ(fs.read("/d/c"), "a");
}

TEST(PowerCutFileSystem, ADirectoryMovesWithItsContentsAndExchangeSwapsTwo) {
  PowerCutFileSystem fs;
  fs.create_directories("/data/x");
  fs.create_directories("/data/y");
  fs.sync_directory("/");
  fs.sync_directory("/data");
  auto f = fs.open("/data/x/f", FileSystem::Open::existing_or_new);
  f->append("in x");
  f->sync();
  fs.sync_directory("/data/x");
  EXPECT_TRUE(fs.exchange("/data/x", "/data/y"));
  EXPECT_EQ(fs.read("/data/y/f"), "in x");
  EXPECT_FALSE(fs.exists("/data/x/f"));
  fs.sync_directory("/data");
  fs.power_on();
  EXPECT_EQ(fs.read("/data/y/f"), "in x");
  fs.set_exchange_supported(false);
  EXPECT_FALSE(fs.exchange("/data/x", "/data/y"));
  EXPECT_EQ(fs.read("/data/y/f"), "in x") << "an unsupported exchange changed something";
}

TEST(PowerCutFileSystem, CountsOperationsAndCutsAtTheArmedOne) {
  PowerCutFileSystem fs;
  fs.create_directories("/d");
  const std::uint64_t start = fs.operations();
  auto f = fs.open("/d/f", FileSystem::Open::existing_or_new);  // 1: a creation
  f->append("x");                                               // 2
  EXPECT_EQ(fs.operations(), start + 2);
  fs.cut_at(2);
  f->append("y");  // 3
  EXPECT_FALSE(fs.is_cut());
  EXPECT_THROW(f->sync(), PowerCut);  // 4: the power goes
  EXPECT_TRUE(fs.is_cut());
  EXPECT_THROW(fs.sync_directory("/d"), PowerCut);
}

TEST(PowerCutFileSystem, ALockIsHeldUntilReleasedOrThePowerGoes) {
  PowerCutFileSystem fs;
  fs.create_directories("/d");
  auto held = fs.lock("/d");
  ASSERT_NE(held, nullptr);
  EXPECT_EQ(fs.lock("/d"), nullptr);
  held.reset();
  auto again = fs.lock("/d");
  EXPECT_NE(again, nullptr);
  fs.sync_directory("/");
  fs.power_on();
  auto after = fs.lock("/d");
  EXPECT_NE(after, nullptr) << "a lock outlived the power";
  again.reset();  // the holder from before the cut lets go late: it releases nothing now
  EXPECT_EQ(fs.lock("/d"), nullptr);
}

}  // namespace
}  // namespace ispars::test
