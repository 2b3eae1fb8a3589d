#include "ispars/planning/builders/known_routes.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace ispars::planning {
namespace {

constexpr std::size_t kFirstSlots = 1024;

std::size_t home(std::uint64_t key, std::size_t slots) {
  // Fibonacci hashing: the top bits of key * 2^64 / phi, as many as the table has.
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ULL) >> (64 - std::countr_zero(slots)));
}

}  // namespace

KnownRoutes::KnownRoutes(std::size_t max_pairs) : per_generation_(max_pairs / 2) {
  if (max_pairs < 2048 || max_pairs > (std::size_t{1} << 30)) {
    throw std::invalid_argument("KnownRoutes: max_pairs must be in 2048..2^30");
  }
  young_.slots.resize(kFirstSlots);
}

std::uint64_t KnownRoutes::key(VertexId a, VertexId b) {
  // (min, max), so a pair has one key in either order; never 0, since a != b.
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

const KnownRoutes::Slot* KnownRoutes::Table::find(std::uint64_t k) const {
  if (slots.empty()) return nullptr;
  const std::size_t mask = slots.size() - 1;
  for (std::size_t i = home(k, slots.size());; i = (i + 1) & mask) {
    if (slots[i].key == k) return &slots[i];
    if (slots[i].key == 0) return nullptr;
  }
}

void KnownRoutes::Table::put(std::uint64_t k, double length) {
  const std::size_t mask = slots.size() - 1;
  for (std::size_t i = home(k, slots.size());; i = (i + 1) & mask) {
    if (slots[i].key == k) {
      slots[i].length = std::min(slots[i].length, length);
      return;
    }
    if (slots[i].key == 0) {
      slots[i] = {k, length};
      ++count;
      return;
    }
  }
}

void KnownRoutes::Table::grow() {
  std::vector<Slot> old(slots.size() * 2);
  old.swap(slots);
  count = 0;
  for (const Slot& s : old) {
    if (s.key != 0) put(s.key, s.length);
  }
}

double KnownRoutes::get(VertexId a, VertexId b) const {
  const std::uint64_t k = key(a, b);
  double best = INFINITY;
  if (const Slot* s = young_.find(k)) best = s->length;
  if (const Slot* s = old_.find(k)) best = std::min(best, s->length);
  return best;
}

void KnownRoutes::remember(VertexId a, VertexId b, double length) {
  if (a == b) return;
  if (young_.count >= per_generation_) {  // the young generation is full: it becomes the old one
    old_ = std::move(young_);
    young_ = Table{};
    young_.slots.resize(kFirstSlots);
    ++dropped_;
  }
  if (2 * (young_.count + 1) > young_.slots.size()) young_.grow();
  young_.put(key(a, b), length);
}

}  // namespace ispars::planning
