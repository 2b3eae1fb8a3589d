// Bitset POI sets: rows, counts, containment and unions, across word boundaries.

#include <gtest/gtest.h>

#include "ispars/roadmap/poi_set.hpp"

namespace ispars {
namespace {

TEST(PoiSet, RowsRoundTripAcrossWords) {
  PoiSetTable table(130);
  EXPECT_EQ(table.words(), 3u);
  table.append(std::vector<PoiId>{0, 63, 64, 129});
  table.append(std::vector<PoiId>{});
  EXPECT_EQ(table.rows(), 2u);
  EXPECT_EQ(table.ids(0), (std::vector<PoiId>{0, 63, 64, 129}));
  EXPECT_TRUE(table.ids(1).empty());
  EXPECT_EQ(count(table.row(0)), 4u);
}

TEST(PoiSet, OutsideAndUnite) {
  PoiSetTable table(200);
  table.append(std::vector<PoiId>{5, 150});
  table.append(std::vector<PoiId>{5});
  std::vector<std::uint64_t> cover(table.words(), 0);
  EXPECT_TRUE(has_outside(table.row(1), cover));
  unite(cover, table.row(1));
  EXPECT_FALSE(has_outside(table.row(1), cover));
  EXPECT_TRUE(has_outside(table.row(0), cover));  // 150 is not covered
  unite(cover, table.row(0));
  EXPECT_FALSE(has_outside(table.row(0), cover));
  EXPECT_EQ(count(cover), 2u);
}

TEST(PoiSet, NoPoisStillCountsRows) {
  PoiSetTable table(0);
  table.append({});
  table.append({});
  EXPECT_EQ(table.rows(), 2u);
  EXPECT_EQ(count(table.row(1)), 0u);
}

}  // namespace
}  // namespace ispars
