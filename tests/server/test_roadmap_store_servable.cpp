// store_quick_problem: what the fleet's announcement checks before it offers a stored copy
// (docs/fleet.md). A bit flipped in any file's magic, or a journal cut below what its head says
// was durable, is named; a healthy store, a journal torn past that length, and one with no head
// pass.

#include <gtest/gtest.h>

#include "roadmap_store_fixture.hpp"

namespace ispars::service {
namespace {

TEST_F(RoadmapStoreTest, AStoreThatCannotBeServedIsToldWithoutReadingItWhole) {
  const auto path = dir_.path() / "bridge";
  {
    auto store = RoadmapStore::create(path, recipe_);
    (void)build_and_commit(*store, 2, 150);
  }
  EXPECT_EQ(store_quick_problem(path), "");
  const std::string journal = slurp(path / "journal.log");
  std::string flipped = journal;
  flipped[3] ^= 0x02;
  spit(path / "journal.log", flipped);
  EXPECT_NE(store_quick_problem(path).find("journal.log does not start as a ISPJRN03 file (damaged at byte 0)"),
            std::string::npos)
      << store_quick_problem(path);
  spit(path / "journal.log", journal.substr(0, journal.size() - 10));  // below the acknowledged length
  EXPECT_NE(store_quick_problem(path).find("and its head says " + std::to_string(journal.size()) + " were durable"),
            std::string::npos)
      << store_quick_problem(path);
  spit(path / "journal.log", journal + "\x01\x02");  // a torn tail past it: recovery cuts it
  EXPECT_EQ(store_quick_problem(path), "");
  spit(path / "journal.log", journal);
  std::filesystem::remove(path / "head");  // a store older than its head file
  EXPECT_EQ(store_quick_problem(path), "");
  spit(path / "snapshot.bin", "ISPSNX03");
  EXPECT_NE(store_quick_problem(path).find("snapshot.bin does not start as a ISPSNP03 file"), std::string::npos);
  spit(path / "snapshot.bin", "ISPS");  // a snapshot is renamed into place whole: no torn header
  EXPECT_NE(store_quick_problem(path).find("snapshot.bin does not start as"), std::string::npos);
}

}  // namespace
}  // namespace ispars::service
