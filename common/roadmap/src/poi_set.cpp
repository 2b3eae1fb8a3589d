#include "ispars/roadmap/poi_set.hpp"

#include <bit>

namespace ispars {

std::size_t PoiSetTable::append(std::span<const PoiId> ids) {
  const std::size_t index = rows();
  bits_.resize(bits_.size() + words_, 0);
  std::uint64_t* row = bits_.data() + index * words_;
  for (const PoiId id : ids) row[id / 64] |= std::uint64_t{1} << (id % 64);
  if (words_ == 0) ++rows_;
  return index;
}

std::vector<PoiId> PoiSetTable::ids(std::size_t i) const {
  std::vector<PoiId> out;
  const PoiBits r = row(i);
  for (std::size_t w = 0; w < r.size(); ++w) {
    std::uint64_t word = r[w];
    while (word != 0) {
      const int bit = std::countr_zero(word);
      out.push_back(static_cast<PoiId>(w * 64 + static_cast<std::size_t>(bit)));
      word &= word - 1;
    }
  }
  return out;
}

std::size_t count(PoiBits set) {
  std::size_t n = 0;
  for (const std::uint64_t word : set) n += static_cast<std::size_t>(std::popcount(word));
  return n;
}

bool has_outside(PoiBits set, std::span<const std::uint64_t> cover) {
  for (std::size_t w = 0; w < set.size(); ++w) {
    if ((set[w] & ~cover[w]) != 0) return true;
  }
  return false;
}

void unite(std::vector<std::uint64_t>& cover, PoiBits set) {
  for (std::size_t w = 0; w < set.size(); ++w) cover[w] |= set[w];
}

}  // namespace ispars
