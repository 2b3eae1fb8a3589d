#include "ispars/params/spec.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>

namespace ispars::params {
namespace {

// A real's text as strtod reads it, the whole text or nothing.
bool read_real(std::string_view text, double& out) {
  const std::string copy(text);
  if (copy.empty() || std::isspace(static_cast<unsigned char>(copy.front()))) return false;
  char* end = nullptr;
  out = std::strtod(copy.c_str(), &end);
  return end == copy.c_str() + copy.size();
}

// Decimal digits with an optional sign, as typed: nothing for anything else (a fraction, an
// exponent, hex, spaces) or past 2^64 - 1; `negative` for a '-' on a non-zero number.
std::optional<std::uint64_t> read_whole(std::string_view text, bool& negative) {
  bool minus = false;
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) {
    minus = text.front() == '-';
    text.remove_prefix(1);
  }
  if (text.empty()) return std::nullopt;
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  negative = minus && value != 0;
  return value;
}

template <class T>
Parsed<T> parse_count(const Spec<T>& spec, std::string_view text) {
  bool negative = false;
  const std::optional<std::uint64_t> whole = read_whole(text, negative);
  if (whole && !negative && *whole <= static_cast<std::uint64_t>(spec.max)) {
    return {static_cast<T>(*whole), problem(spec, static_cast<T>(*whole))};
  }
  double real = 0.0;
  if (!whole && !read_real(text, real)) return {0, fmt::format("expected a whole number, got '{}'", text)};
  return {0, fmt::format("must be {}, got {}", range_text(spec), text)};  // negative, a fraction, too large
}

}  // namespace

std::string flag_name(std::string_view name) {
  std::string flag = "--" + std::string(name);
  for (char& c : flag) {
    if (c == '_') c = '-';
  }
  return flag;
}

template <class T>
std::string range_text(const Spec<T>& spec) {
  if constexpr (std::is_same_v<T, bool>) {
    return "true or false";
  } else if constexpr (std::is_same_v<T, double>) {
    return fmt::format("in {}{}, {}]", spec.lower == Lower::open ? '(' : '[', spec.min, spec.max);
  } else {
    return fmt::format("a whole number in {}{}, {}]", spec.lower == Lower::open ? '(' : '[', spec.min, spec.max);
  }
}

template <class T>
std::string problem(const Spec<T>& spec, T value) {
  if constexpr (std::is_same_v<T, bool>) {
    return spec.rule ? spec.rule(value) : std::string();
  } else {
    bool ok = value <= spec.max && (spec.lower == Lower::open ? value > spec.min : value >= spec.min);
    if constexpr (std::is_same_v<T, double>) ok = ok && std::isfinite(value);
    if (!ok) return fmt::format("must be {}, got {}", range_text(spec), value);
    return spec.rule ? spec.rule(value) : std::string();
  }
}

template <class T>
Parsed<T> parse(const Spec<T>& spec, std::string_view text) {
  if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "1" || text == "yes" || text == "on") return {true, {}};
    if (text == "false" || text == "0" || text == "no" || text == "off") return {false, {}};
    return {false, fmt::format("expected true or false, got '{}'", text)};
  } else if constexpr (std::is_same_v<T, double>) {
    double value = 0.0;
    if (!read_real(text, value)) return {0.0, fmt::format("expected a number, got '{}'", text)};
    return {value, problem(spec, value)};
  } else {
    return parse_count(spec, text);
  }
}

#define ISPARS_PARAM_TYPE(T)                          \
  template std::string range_text<T>(const Spec<T>&); \
  template std::string problem<T>(const Spec<T>&, T); \
  template Parsed<T> parse<T>(const Spec<T>&, std::string_view);
ISPARS_PARAM_TYPE(double)
ISPARS_PARAM_TYPE(std::uint64_t)
ISPARS_PARAM_TYPE(std::uint32_t)
ISPARS_PARAM_TYPE(int)
ISPARS_PARAM_TYPE(bool)
#undef ISPARS_PARAM_TYPE

}  // namespace ispars::params
