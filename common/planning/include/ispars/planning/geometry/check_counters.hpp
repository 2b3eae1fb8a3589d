#pragma once
// Counters of the geometric checks a planner pays for: the paper's hardware-independent cost.

#include <atomic>
#include <cstdint>

namespace ispars::planning {

/// A snapshot of how many checks were made.
struct CheckCounts {
  std::uint64_t point = 0;    ///< Point validity checks.
  std::uint64_t segment = 0;  ///< Segment (swept-sphere) validity checks.
  std::uint64_t rays = 0;     ///< Line-of-sight rays cast for visibility.

  CheckCounts& operator+=(const CheckCounts& o) {
    point += o.point;
    segment += o.segment;
    rays += o.rays;
    return *this;
  }
  friend CheckCounts operator+(CheckCounts a, const CheckCounts& b) { return a += b; }
  friend CheckCounts operator-(CheckCounts a, const CheckCounts& b) {
    a.point -= b.point;
    a.segment -= b.segment;
    a.rays -= b.rays;
    return a;
  }
  friend bool operator==(const CheckCounts&, const CheckCounts&) = default;
};

/// Thread-safe counters that const queries bump (relaxed atomics: totals, not ordering).
class CheckCounters {
 public:
  void add_point() const { point_.fetch_add(1, std::memory_order_relaxed); }
  void add_segment() const { segment_.fetch_add(1, std::memory_order_relaxed); }
  void add_rays(std::uint64_t n) const { rays_.fetch_add(n, std::memory_order_relaxed); }
  [[nodiscard]] CheckCounts snapshot() const {
    return {point_.load(std::memory_order_relaxed), segment_.load(std::memory_order_relaxed),
            rays_.load(std::memory_order_relaxed)};
  }

 private:
  mutable std::atomic<std::uint64_t> point_{0};
  mutable std::atomic<std::uint64_t> segment_{0};
  mutable std::atomic<std::uint64_t> rays_{0};
};

}  // namespace ispars::planning
