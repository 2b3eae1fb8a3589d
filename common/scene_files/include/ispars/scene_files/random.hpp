#pragma once
// A seeded random number generator whose output is the same on every machine and compiler.
//
// std::uniform_real_distribution and friends are implementation-defined, so roadmaps built with
// them would differ between standard libraries. Rng defines every conversion itself.

#include <cstdint>

#include "ispars/roadmap/vec.hpp"

namespace ispars::scene_files {

/// xoshiro256** seeded through splitmix64: fast, small state, identical streams everywhere.
class Rng {
 public:
  explicit Rng(std::uint64_t seed);

  /// The next 64 random bits.
  std::uint64_t next_u64();
  /// Skips `n` draws of next_u64 (every other draw is made of them: uniform01 takes one,
  /// uniform_in three).
  void discard(std::uint64_t n);
  /// Uniform in [0, 1), with 53 random bits.
  double uniform01();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi);
  /// Uniform integer in [0, n), without modulo bias; n must be positive.
  std::uint64_t below(std::uint64_t n);
  /// Uniform point in the box.
  Vec3 uniform_in(const Aabb& box);
  /// Uniform direction on the unit sphere.
  Vec3 unit_vector();

 private:
  std::uint64_t s_[4];
};

}  // namespace ispars::scene_files
