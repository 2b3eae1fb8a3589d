#include "ispars/roadmap/poi_set.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <string>

namespace ispars {

std::size_t PoiSetTable::append(std::span<const PoiId> ids) {
  const std::size_t index = rows();
  bits_.resize(bits_.size() + words_, 0);
  std::uint64_t* row = bits_.data() + index * words_;
  for (const PoiId id : ids) row[id / 64] |= std::uint64_t{1} << (id % 64);
  if (words_ == 0) ++rows_;
  return index;
}

void PoiSetTable::widen(std::size_t poi_count) {
  if (poi_count < poi_count_) {
    throw std::invalid_argument("POI sets cannot shrink from " + std::to_string(poi_count_) + " to " +
                                std::to_string(poi_count) + " POIs");
  }
  const std::size_t words = poi_words(poi_count);
  if (words != words_) {
    const std::size_t n = rows();
    std::vector<std::uint64_t> wider(n * words, 0);
    for (std::size_t r = 0; r < n; ++r) {
      std::copy_n(bits_.begin() + static_cast<std::ptrdiff_t>(r * words_), words_,
                  wider.begin() + static_cast<std::ptrdiff_t>(r * words));
    }
    bits_ = std::move(wider);
    words_ = words;
    rows_ = 0;  // counted by bits_ from now on, as in a table built this wide
  }
  poi_count_ = poi_count;
}

void PoiSetTable::add(std::size_t i, std::span<const PoiId> ids) {
  if (i >= rows()) throw std::out_of_range("no POI set row " + std::to_string(i));
  for (const PoiId id : ids) {
    if (id >= poi_count_) {
      throw std::out_of_range("POI " + std::to_string(id) + " is not one of the " + std::to_string(poi_count_));
    }
  }
  std::uint64_t* row = bits_.data() + i * words_;
  for (const PoiId id : ids) row[id / 64] |= std::uint64_t{1} << (id % 64);
}

std::vector<PoiId> PoiSetTable::ids(std::size_t i) const {
  std::vector<PoiId> out;
  append_ids(i, out);
  return out;
}

void PoiSetTable::append_ids(std::size_t i, std::vector<PoiId>& out) const {
  const PoiBits r = row(i);
  for (std::size_t w = 0; w < r.size(); ++w) {
    std::uint64_t word = r[w];
    while (word != 0) {
      const int bit = std::countr_zero(word);
      out.push_back(static_cast<PoiId>(w * 64 + static_cast<std::size_t>(bit)));
      word &= word - 1;
    }
  }
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
