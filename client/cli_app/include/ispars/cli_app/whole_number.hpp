#pragma once
// Whole-number flags of `ispars` that are no declared parameter (--edges, a tour's
// targets): read as params::parse reads a count, so "-5" is a negative number (not 2^64 - 5),
// "1e3" and "2.5" are not whole numbers, and a refusal names the range in the same words as every
// declared parameter's ("must be a whole number in [1, 1000], got -5").

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>

namespace ispars::cli_app {

/// Any seed: every 64-bit value draws its own stream.
inline constexpr std::uint64_t kMaxSeed = std::numeric_limits<std::uint64_t>::max();

/// A CLI11 check, run on the text before CLI11 converts it: a whole number in [min, max].
[[nodiscard]] CLI::Validator whole_number(std::uint64_t min, std::uint64_t max);

}  // namespace ispars::cli_app
