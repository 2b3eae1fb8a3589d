// Bitset POI sets: rows, counts, containment and unions, across word boundaries; widened for new POIs.

#include <gtest/gtest.h>

#include <stdexcept>

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

// Widening for new POIs (an inspection task): every row keeps its ids, the new POIs can be added
// to any row, and the table equals the one built that wide from the start with the same rows.
TEST(PoiSet, AWidenedTableEqualsOneBuiltWideWithTheSameRows) {
  for (const std::size_t from : {std::size_t{0}, std::size_t{5}, std::size_t{64}, std::size_t{130}}) {
    for (const std::size_t to : {from, from + 1, from + 60, from + 200}) {
      PoiSetTable grown(from);
      PoiSetTable wide(to);
      for (std::size_t r = 0; r < 4; ++r) {
        std::vector<PoiId> ids;
        for (std::size_t id = r; id < from; id += 7) ids.push_back(static_cast<PoiId>(id));
        grown.append(ids);
        wide.append(ids);
      }
      grown.widen(to);
      EXPECT_EQ(grown.words(), poi_words(to));
      EXPECT_EQ(grown.rows(), 4u);
      for (std::size_t r = 0; r < 4; ++r) {
        std::vector<PoiId> extra;
        for (std::size_t id = from + r; id < to; id += 3) extra.push_back(static_cast<PoiId>(id));
        grown.add(r, extra);
        wide.add(r, extra);
      }
      EXPECT_TRUE(grown == wide) << from << " -> " << to;
      const std::vector<PoiId> more{static_cast<PoiId>(to - (to > 0 ? 1 : 0))};
      if (to > 0) {
        grown.append(more);
        wide.append(more);
        EXPECT_TRUE(grown == wide) << from << " -> " << to << " then a row";
      }
    }
  }
}

TEST(PoiSet, WideningNeverShrinksAndAddingStaysInRange) {
  PoiSetTable table(70);
  table.append(std::vector<PoiId>{1, 69});
  EXPECT_THROW(table.widen(69), std::invalid_argument);
  EXPECT_THROW(table.add(0, std::vector<PoiId>{70}), std::out_of_range);
  EXPECT_THROW(table.add(1, std::vector<PoiId>{0}), std::out_of_range);  // no row 1
  EXPECT_EQ(table.ids(0), (std::vector<PoiId>{1, 69}));                  // nothing changed
  table.widen(71);
  table.add(0, std::vector<PoiId>{70});
  EXPECT_EQ(table.ids(0), (std::vector<PoiId>{1, 69, 70}));
}

}  // namespace
}  // namespace ispars
