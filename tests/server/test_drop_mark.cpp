// Drop marks: a scene's drop remembered after its store is gone, durably, whatever the power does.

#include "ispars/service/drop_mark.hpp"

#include <gtest/gtest.h>

#include "support/power_cut_fs.hpp"

namespace ispars::service {
namespace {

const std::filesystem::path kData = "/data";

TEST(DropMark, AMarkNamesTheDropsGenerationAndTheListingSkipsWhatIsNotAMark) {
  test::PowerCutFileSystem fs;
  fs.create_directories(kData);
  EXPECT_FALSE(dropped_generation(kData / "tower", fs));
  EXPECT_TRUE(list_drop_marks(kData, fs).empty());
  mark_dropped(kData / "tower", 42, fs);
  mark_dropped(kData / "bridge", 7, fs);
  mark_dropped(kData / "tower", 43, fs);  // dropped again, later
  EXPECT_EQ(dropped_generation(kData / "tower", fs), 43u);
  // Garbage and an interrupted write's temporary file are not marks.
  fs.open(kData / ".drops" / "junk", FileSystem::Open::truncated)->append("not a mark\n");
  fs.open(kData / ".drops" / "zero", FileSystem::Open::truncated)->append("generation 0\n");
  fs.open(kData / ".drops" / "tower.tmp", FileSystem::Open::truncated)->append("generation 99\n");
  const std::vector<DropMark> marks = list_drop_marks(kData, fs);
  ASSERT_EQ(marks.size(), 2u);
  EXPECT_EQ(marks[0].scene, "bridge");
  EXPECT_EQ(marks[0].generation, 7u);
  EXPECT_EQ(marks[1].scene, "tower");
  EXPECT_EQ(marks[1].generation, 43u);
  EXPECT_FALSE(dropped_generation(kData / "junk", fs));
  // A mark whose generation changed by one digit fails its seal and is not believed; an
  // unsealed mark (written before seals) still is.
  std::string text = *fs.read(kData / ".drops" / "bridge");
  ASSERT_NE(text.find("generation 7\n"), std::string::npos) << text;
  text[text.find("generation 7\n") + 11] = '8';
  fs.open(kData / ".drops" / "bridge", FileSystem::Open::truncated)->append(text);
  EXPECT_FALSE(dropped_generation(kData / "bridge", fs));
  fs.open(kData / ".drops" / "bridge", FileSystem::Open::truncated)->append("generation 7\nold mark\n");
  EXPECT_EQ(dropped_generation(kData / "bridge", fs), 7u);
}

// A power cut at any operation of a mark's write leaves the old mark or the new one, whole; once
// mark_dropped returned, the new one survives any cut.
TEST(DropMark, APowerCutAnywhereLeavesTheOldMarkOrTheNewOneAndAReturnedMarkSurvives) {
  std::uint64_t writes = 0;
  {
    test::PowerCutFileSystem fs;
    fs.create_directories(kData);
    fs.sync_directory("/");
    const std::uint64_t before = fs.operations();
    mark_dropped(kData / "tower", 1, fs);
    writes = fs.operations() - before;
  }
  ASSERT_GT(writes, 2u);
  for (const bool first : {true, false}) {
    for (std::uint64_t cut = 1; cut <= writes + 1; ++cut) {
      SCOPED_TRACE((first ? "first mark, cut at " : "second mark, cut at ") + std::to_string(cut));
      test::PowerCutFileSystem fs;
      fs.create_directories(kData);
      fs.sync_directory("/");
      if (!first) mark_dropped(kData / "tower", 1, fs);
      fs.cut_at(cut);
      bool returned = false;
      try {
        mark_dropped(kData / "tower", 2, fs);
        returned = true;
      } catch (const test::PowerCut&) {
      }
      fs.cut_at(1);  // the power goes right after, whether the write finished or not
      try {
        fs.sync_directory("/");
      } catch (const test::PowerCut&) {
      }
      fs.power_on();
      const auto generation = dropped_generation(kData / "tower", fs);
      if (returned) {
        EXPECT_EQ(generation, 2u);
      } else if (first) {
        EXPECT_TRUE(!generation || *generation == 2u);
      } else {
        ASSERT_TRUE(generation);
        EXPECT_TRUE(*generation == 1u || *generation == 2u);
      }
    }
  }
}

}  // namespace
}  // namespace ispars::service
