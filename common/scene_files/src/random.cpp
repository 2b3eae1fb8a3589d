#include "ispars/scene_files/random.hpp"

#include <cmath>

namespace ispars::scene_files {
namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

Rng::Rng(std::uint64_t seed) {
  for (auto& word : s_) word = splitmix64(seed);
}

std::uint64_t Rng::next_u64() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

void Rng::discard(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i) (void)next_u64();
}

double Rng::uniform01() { return static_cast<double>(next_u64() >> 11) * 0x1.0p-53; }

double Rng::uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }

std::uint64_t Rng::below(std::uint64_t n) {
  // Rejection of the short top range keeps every value equally likely.
  const std::uint64_t limit = ~std::uint64_t{0} - (~std::uint64_t{0} % n);
  std::uint64_t x = next_u64();
  while (x >= limit) x = next_u64();
  return x % n;
}

Vec3 Rng::uniform_in(const Aabb& box) {
  const double x = uniform(box.min.x(), box.max.x());
  const double y = uniform(box.min.y(), box.max.y());
  const double z = uniform(box.min.z(), box.max.z());
  return {x, y, z};
}

Vec3 Rng::unit_vector() {
  // Rejection from the cube: only arithmetic and a correctly rounded sqrt, so the result is the
  // same bit for bit on every IEEE machine (cos/sin differ between libm versions).
  for (;;) {
    const double x = uniform(-1.0, 1.0);
    const double y = uniform(-1.0, 1.0);
    const double z = uniform(-1.0, 1.0);
    const double n2 = x * x + y * y + z * z;
    if (n2 > 1e-12 && n2 <= 1.0) {
      const double n = std::sqrt(n2);
      return {x / n, y / n, z / n};
    }
  }
}

}  // namespace ispars::scene_files
