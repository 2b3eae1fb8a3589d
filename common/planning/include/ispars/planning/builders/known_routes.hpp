#pragma once
// Routes between pairs of sparse vertices found so far, so that the stretch rules skip the
// searches they already answered (spars_spanner.cpp).

#include <cstdint>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars::planning {

/// Upper bounds on the sparse route between pairs of vertices: an edge's length, or the length
/// of a route a search found. Routes only get shorter as G_s grows, so a bound stays true. It is
/// a cache: a pair it has forgotten is searched again and gives the same answer, so forgetting
/// changes no decision. It holds at most `max_pairs` pairs in two generations: when the young one
/// holds half of them it becomes the old one, and the old one is forgotten. Each is open
/// addressing on one flat array (16 bytes a slot, at most half of them used): a lookup is a hash
/// and, mostly, one cache line.
class KnownRoutes {
 public:
  /// `max_pairs`: 2048 .. 2^30.
  explicit KnownRoutes(std::size_t max_pairs = std::size_t{1} << 22);

  /// The shortest route remembered between a and b (either order); infinity when none.
  [[nodiscard]] double get(VertexId a, VertexId b) const;
  /// Remembers a route of `length` between a and b (a != b), keeping the shorter of two.
  void remember(VertexId a, VertexId b, double length);
  /// Pairs remembered now (a pair in both generations counts twice).
  [[nodiscard]] std::size_t size() const { return young_.count + old_.count; }
  /// Times the old generation was forgotten.
  [[nodiscard]] std::size_t generations_dropped() const { return dropped_; }

 private:
  struct Slot {
    std::uint64_t key = 0;  // 0: empty (a pair is never (0, 0))
    double length = 0.0;
  };
  struct Table {
    std::vector<Slot> slots;
    std::size_t count = 0;
    [[nodiscard]] const Slot* find(std::uint64_t key) const;
    void put(std::uint64_t key, double length);  // keeps the shorter; the table must have room
    void grow();
  };
  [[nodiscard]] static std::uint64_t key(VertexId a, VertexId b);

  std::size_t per_generation_;
  Table young_;
  Table old_;
  std::size_t dropped_ = 0;
};

}  // namespace ispars::planning
