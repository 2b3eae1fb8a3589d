#pragma once
// Compact POI sets: one bitset per vertex, all stored in one contiguous table.

#include <cstdint>
#include <span>
#include <vector>

#include "ispars/roadmap/poi_id.hpp"

namespace ispars {

/// A bitset over the scene's POIs, as a view of 64-bit words.
using PoiBits = std::span<const std::uint64_t>;

/// Number of 64-bit words a set over `poi_count` POIs needs.
[[nodiscard]] constexpr std::size_t poi_words(std::size_t poi_count) { return (poi_count + 63) / 64; }

/// The POI sets of a growing list of vertices, row after row in one vector (cache-friendly
/// unions and differences in the inspection test).
class PoiSetTable {
 public:
  explicit PoiSetTable(std::size_t poi_count = 0) : poi_count_(poi_count), words_(poi_words(poi_count)) {}

  /// Appends a row holding `ids`; returns its index.
  std::size_t append(std::span<const PoiId> ids);
  /// Grows the set of POIs to `poi_count` (ids only append: every row keeps its ids, and the new
  /// POIs are in no row). The table then equals one built with `poi_count` from the start. Throws
  /// std::invalid_argument when `poi_count` is below poi_count(). O(rows x words) when the rows
  /// need another word, else O(1).
  void widen(std::size_t poi_count);
  /// Adds `ids` to row i (each below poi_count(); throws std::out_of_range otherwise).
  void add(std::size_t i, std::span<const PoiId> ids);
  [[nodiscard]] PoiBits row(std::size_t i) const { return {bits_.data() + i * words_, words_}; }
  [[nodiscard]] std::size_t rows() const { return words_ == 0 ? rows_ : bits_.size() / words_; }
  [[nodiscard]] std::size_t poi_count() const { return poi_count_; }
  [[nodiscard]] std::size_t words() const { return words_; }
  /// The ids in row i, ascending.
  [[nodiscard]] std::vector<PoiId> ids(std::size_t i) const;
  /// Appends the ids in row i, ascending, to `out`: ids() without a vector per row.
  void append_ids(std::size_t i, std::vector<PoiId>& out) const;
  /// The same POI count and the same rows.
  friend bool operator==(const PoiSetTable&, const PoiSetTable&) = default;

 private:
  std::size_t poi_count_;
  std::size_t words_;
  std::size_t rows_ = 0;  // only used when there are no POIs (zero-width rows)
  std::vector<std::uint64_t> bits_;
};

/// Number of POIs in the set.
[[nodiscard]] std::size_t count(PoiBits set);
/// True when `set` has a POI that `cover` lacks.
[[nodiscard]] bool has_outside(PoiBits set, std::span<const std::uint64_t> cover);
/// cover |= set.
void unite(std::vector<std::uint64_t>& cover, PoiBits set);

}  // namespace ispars
