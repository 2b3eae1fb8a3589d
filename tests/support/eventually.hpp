#pragma once
// Waiting on a condition, never on a fixed sleep. eventually() looks at a predicate until it holds
// or a bound passes; throughout() checks that one keeps holding for a while. One helper for every
// test, so that a wait reads as what it waits for, and a failure says what never happened.
//
//   ASSERT_TRUE(eventually([&] { return client.daemons().size() == 2; }, 30s, "the client hears both daemons"));

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>

namespace ispars::test {

/// How often a condition is looked at again: short against the bounds (seconds), long against
/// one look (a DDS read, a log scan, a metrics scrape).
inline constexpr std::chrono::milliseconds kPollPeriod{50};

/// Looks at `holds()` at once, then every `period`, until it is true or `timeout` has passed:
/// success, or a failure naming `what` and the bound.
template <class Predicate>
[[nodiscard]] testing::AssertionResult eventually(Predicate&& holds, std::chrono::milliseconds timeout,
                                                  const std::string& what,
                                                  std::chrono::milliseconds period = kPollPeriod) {
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    if (holds()) return testing::AssertionSuccess();
    const auto waited = std::chrono::steady_clock::now() - start;
    if (waited >= timeout) return testing::AssertionFailure() << what << ": not within " << timeout.count() << " ms";
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(period, timeout - waited));
  }
}

/// Looks at `holds()` every `period` for `duration`: success if it held at every look, else a
/// failure naming `what` and how long it had held.
template <class Predicate>
[[nodiscard]] testing::AssertionResult throughout(Predicate&& holds, std::chrono::milliseconds duration,
                                                  const std::string& what,
                                                  std::chrono::milliseconds period = kPollPeriod) {
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const auto held = std::chrono::steady_clock::now() - start;
    if (!holds()) {
      return testing::AssertionFailure() << what << ": stopped holding after "
                                         << std::chrono::duration_cast<std::chrono::milliseconds>(held).count()
                                         << " ms";
    }
    if (held >= duration) return testing::AssertionSuccess();
    std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(period, duration - held));
  }
}

}  // namespace ispars::test
