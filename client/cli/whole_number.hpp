#pragma once
// Whole-number flags of `ispars`, read as the user typed them: "-5" is a negative number (not
// 2^64 - 5), "1e3" and "2.5" are not whole numbers, and a refusal names the flag's range in its
// own unit.

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

namespace ispars::cli {

/// The number `text` spells in decimal digits, with an optional sign; nothing when it is not
/// one (empty, a fraction, an exponent, hex, spaces) or lies outside [-(2^64 - 1), 2^64 - 1].
/// `negative` is set for a '-' sign on a non-zero number.
[[nodiscard]] std::optional<std::uint64_t> parse_whole_number(std::string_view text, bool& negative);

/// Any seed: every 64-bit value draws its own stream.
inline constexpr std::uint64_t kMaxSeed = std::numeric_limits<std::uint64_t>::max();

/// A CLI11 check, run on the text before CLI11 converts it: a whole number in [min, max], else
/// "must be a whole number of <unit> from <min> to <max>, got '<text>'" (without "of <unit>" when
/// `unit` is empty).
[[nodiscard]] CLI::Validator whole_number(std::uint64_t min, std::uint64_t max, const std::string& unit);

}  // namespace ispars::cli
