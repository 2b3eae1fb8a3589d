#pragma once
// Small timing helpers for the lab's benchmarks: medians of per-call times over batches.

#include <chrono>
#include <cstddef>
#include <functional>
#include <vector>

namespace ispars::lab {

/// Peak resident set size of this process in MiB (VmHWM), 0 when unknown.
[[nodiscard]] double peak_rss_mib();

/// Seconds on a monotonic clock.
[[nodiscard]] double now_seconds();

/// Median of the values (the mean of the two middle ones for an even count); 0 when empty.
[[nodiscard]] double median(std::vector<double> values);

/// Calls `call(i)` for i in [0, count), timing batches of `batch` calls; returns the median over
/// batches of the per-call time in nanoseconds (batching keeps clock overhead out of sub-us calls).
[[nodiscard]] double median_ns_per_call(std::size_t count, std::size_t batch,
                                        const std::function<void(std::size_t)>& call);

}  // namespace ispars::lab
