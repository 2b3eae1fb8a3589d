#pragma once
// Routes between pairs of sparse vertices found so far, so that the stretch rules skip the
// searches they already answered (spars_stretch.cpp).

#include <cstdint>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// Upper bounds on the sparse route between pairs of vertices: an edge's length, or the length
/// of a route a search found. Routes only get shorter as G_s grows, so a bound stays true. It is
/// a cache: a pair it has forgotten is searched again and gives the same answer, so forgetting
/// changes no decision. It holds at most `max_pairs` pairs (16 bytes each, at most half of its
/// slots used) and forgets them all when full. Open addressing on one flat array: a lookup is a
/// hash and, mostly, one cache line.
class KnownRoutes {
 public:
  /// `max_pairs`: 1024 .. 2^30.
  explicit KnownRoutes(std::size_t max_pairs = std::size_t{1} << 22);

  /// The shortest route remembered between a and b (either order); infinity when none.
  [[nodiscard]] double get(VertexId a, VertexId b) const;
  /// Remembers a route of `length` between a and b (a != b), keeping the shorter of two.
  void remember(VertexId a, VertexId b, double length);
  /// Pairs remembered now.
  [[nodiscard]] std::size_t size() const { return count_; }
  /// Times it forgot everything because it was full.
  [[nodiscard]] std::size_t resets() const { return resets_; }
  /// Forgets every pair.
  void clear();

 private:
  struct Slot {
    std::uint64_t key = 0;  // 0: empty (a pair is never (0, 0))
    double length = 0.0;
  };
  [[nodiscard]] static std::uint64_t key(VertexId a, VertexId b);
  [[nodiscard]] std::size_t home(std::uint64_t key) const;
  void grow();

  std::size_t max_pairs_;
  std::vector<Slot> slots_;
  std::size_t count_ = 0;
  std::size_t resets_ = 0;
};

}  // namespace ispars
