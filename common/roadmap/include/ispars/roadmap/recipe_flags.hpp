#pragma once
// The build recipe's declared parameters (build_recipe.hpp) as command-line flags: the flag of
// `stretch_slack_after` is --stretch-slack-after, typed as declared (a count parses as an
// integer), checked against the declared range, with the declared doc as its help. Header-only,
// so that only the programs that parse flags (ispars-lab, ispars-bench) need CLI11.

#include <CLI/CLI.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "ispars/roadmap/build_recipe.hpp"

namespace ispars {

/// "--stretch-slack-after" for the parameter "stretch_slack_after".
[[nodiscard]] inline std::string recipe_flag_name(std::string_view parameter) {
  std::string flag = "--" + std::string(parameter);
  for (char& c : flag) {
    if (c == '_') c = '-';
  }
  return flag;
}

/// Declares the flag of the recipe parameter `name` on `command`, parsed into `value`, whose type
/// must be the parameter's (double for a real, std::uint64_t for a count: std::logic_error
/// otherwise, a programming error). The declared range is checked as CLI11 parses.
template <class T>
CLI::Option* add_recipe_flag(CLI::App& command, std::string_view name, T& value) {
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, std::uint64_t>, "a real or a count");
  const RecipeParameter& p = recipe_override(name);
  if (p.whole() != std::is_same_v<T, std::uint64_t>) {
    throw std::logic_error("recipe parameter " + std::string(name) + " is declared with another type");
  }
  return command.add_option(recipe_flag_name(name), value, std::string(p.doc))->check(CLI::Range(p.min, p.max));
}

}  // namespace ispars
