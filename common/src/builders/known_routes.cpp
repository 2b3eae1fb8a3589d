#include "ispars/builders/known_routes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

namespace ispars {
namespace {

constexpr std::size_t kFirstSlots = 1024;

}  // namespace

KnownRoutes::KnownRoutes(std::size_t max_pairs) : max_pairs_(max_pairs), slots_(kFirstSlots) {
  if (max_pairs < 1024 || max_pairs > (std::size_t{1} << 30)) {
    throw std::invalid_argument("KnownRoutes: max_pairs must be in 1024..2^30");
  }
}

std::uint64_t KnownRoutes::key(VertexId a, VertexId b) {
  // (min, max), so a pair has one key in either order; never 0, since a != b.
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

std::size_t KnownRoutes::home(std::uint64_t k) const {
  // Fibonacci hashing: the top bits of k * 2^64 / phi, as many as the table has.
  const int bits = std::countr_zero(slots_.size());
  return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ULL) >> (64 - bits));
}

double KnownRoutes::get(VertexId a, VertexId b) const {
  const std::uint64_t k = key(a, b);
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = home(k);; i = (i + 1) & mask) {
    if (slots_[i].key == k) return slots_[i].length;
    if (slots_[i].key == 0) return INFINITY;
  }
}

void KnownRoutes::remember(VertexId a, VertexId b, double length) {
  if (a == b) return;
  if (2 * (count_ + 1) > slots_.size()) grow();
  const std::uint64_t k = key(a, b);
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t i = home(k);; i = (i + 1) & mask) {
    if (slots_[i].key == k) {
      slots_[i].length = std::min(slots_[i].length, length);
      return;
    }
    if (slots_[i].key == 0) {
      slots_[i] = {k, length};
      ++count_;
      return;
    }
  }
}

void KnownRoutes::clear() {
  std::fill(slots_.begin(), slots_.end(), Slot{});
  count_ = 0;
}

void KnownRoutes::grow() {
  if (slots_.size() >= 2 * max_pairs_) {  // full: forget everything (a cache; see the header)
    clear();
    ++resets_;
    return;
  }
  std::vector<Slot> old(slots_.size() * 2);
  old.swap(slots_);
  count_ = 0;
  const std::size_t mask = slots_.size() - 1;
  for (const Slot& s : old) {
    if (s.key == 0) continue;
    std::size_t i = home(s.key);
    while (slots_[i].key != 0) i = (i + 1) & mask;
    slots_[i] = s;
    ++count_;
  }
}

}  // namespace ispars
