#pragma once
// A parameter declared once: its name, its type, its range, one line of doc, and whether a
// running daemon must restart to take a change. The archives (fields.hpp: checks, text and
// overlays; json_archive.hpp; cli_archive.hpp) read these declarations and never restate a range:
// the words of every range error come from range_text().

#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

namespace ispars::params {

/// Whether a range's lower bound is accepted itself (closed) or only what lies above it (open:
/// "positive" for a bound of 0).
enum class Lower { closed, open };

/// The types a parameter may have: a real, a count (an integer of at least 0, read as signed and
/// then range-checked, so that -1 is refused rather than wrapped; an `int` count is an id such as
/// a DDS domain), or a switch. Text and lists are declared by text_spec.hpp.
template <class T>
inline constexpr bool kParamType =
    std::is_same_v<T, double> || std::is_same_v<T, std::uint64_t> || std::is_same_v<T, std::uint32_t> ||
    std::is_same_v<T, int> || std::is_same_v<T, bool>;

/// One parameter's declaration. Its default is the initialiser of the field it describes.
template <class T>
struct Spec {
  static_assert(kParamType<T>, "a parameter is a double, a std::uint64_t, a std::uint32_t, an int or a bool");
  std::string_view name;  ///< snake_case; its flag is --name-with-dashes
  T min{};                ///< the least value accepted (excluded when lower is open; at least 0 for a count)
  T max{};                ///< the largest value accepted (included)
  std::string_view doc;   ///< one line: what it is
  Lower lower = Lower::closed;
  bool needs_restart = false;  ///< a daemon setting a running daemon takes only on restart
  /// What a value must be besides its range ("0 or at least 16"): why it is not, or empty.
  std::string (*rule)(T value) = nullptr;
  std::string_view alias = {};  ///< an older name, still accepted as a flag
};

/// The accepted values in words: "in [1, 100]", "in (0, 1000000]", "a whole number in [0, 5]",
/// "true or false".
template <class T>
[[nodiscard]] std::string range_text(const Spec<T>& spec);

/// Why `value` is not accepted ("must be in [1, 100], got 150", or what the rule says), or empty
/// when it is.
template <class T>
[[nodiscard]] std::string problem(const Spec<T>& spec, T value);

/// A value read from text, or why it could not be: `problem` empty when `value` holds.
template <class T>
struct Parsed {
  T value{};
  std::string problem;
};

/// Reads `text` as `spec`'s type and checks it against its range. A count is read as a signed
/// whole number first, so "-1" and "1.5" are refused with the range in words; a real must be
/// finite; a switch is true/false, 1/0, yes/no or on/off.
template <class T>
[[nodiscard]] Parsed<T> parse(const Spec<T>& spec, std::string_view text);

/// The type's name as help texts show it: "FLOAT", "INT" or "BOOL".
template <class T>
[[nodiscard]] constexpr std::string_view type_name() {
  if constexpr (std::is_same_v<T, double>) return "FLOAT";
  if constexpr (std::is_same_v<T, bool>) return "BOOL";
  return "INT";
}

/// "--stretch-slack-after" for the name "stretch_slack_after".
[[nodiscard]] std::string flag_name(std::string_view name);

}  // namespace ispars::params
