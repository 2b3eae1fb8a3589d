#include "whole_number.hpp"

#include <fmt/format.h>

#include <limits>

namespace ispars::cli {

std::optional<std::uint64_t> parse_whole_number(std::string_view text, bool& negative) {
  negative = false;
  bool minus = false;
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) {
    minus = text.front() == '-';
    text.remove_prefix(1);
  }
  if (text.empty()) return std::nullopt;
  constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
  std::uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (value > (kMax - digit) / 10) return std::nullopt;
    value = value * 10 + digit;
  }
  negative = minus && value != 0;
  return value;
}

CLI::Validator whole_number(std::uint64_t min, std::uint64_t max, const std::string& unit) {
  const std::string range =
      fmt::format("a whole number{} from {} to {}", unit.empty() ? "" : " of " + unit, min, max);
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        bool negative = false;
        const std::optional<std::uint64_t> value = parse_whole_number(text, negative);
        if (value && !negative && *value >= min && *value <= max) return {};
        return fmt::format("must be {}, got '{}'", range, text);
      },
      fmt::format("{} to {}{}", min, max, unit.empty() ? "" : " " + unit));
}

}  // namespace ispars::cli
