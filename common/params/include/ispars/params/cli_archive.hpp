#pragma once
// A struct's declared parameters (fields.hpp) as CLI11 flags: `stretch_slack_after` becomes
// --stretch-slack-after INT, read as its declaration says (a count as a signed whole number, then
// range-checked) with the declared doc and range as its help; a text parameter (text_spec.hpp)
// becomes --name TEXT, checked against its length and rule. Header-only, so that only the
// programs that parse flags need CLI11.

#include <CLI/CLI.hpp>

#include <string>
#include <string_view>

#include "ispars/params/fields.hpp"
#include "ispars/params/text_spec.hpp"

namespace ispars::params {

/// Declares the flag of `spec` on `command` (and of its alias, when it has one), parsed into
/// `member` (a T or a std::optional<T>).
template <class T, class Member>
CLI::Option* add_flag(CLI::App& command, const Spec<T>& spec, Member& member) {
  const std::string flag = flag_name(spec.name);
  const std::string names = spec.alias.empty() ? flag : flag + "," + flag_name(spec.alias);
  auto* option = command.add_option_function<std::string>(
      names,
      [spec, &member, flag](const std::string& text) {  // spec by value: a temporary declaration is safe
        const Parsed<T> parsed = parse(spec, text);
        if (!parsed.problem.empty()) throw CLI::ValidationError(flag, parsed.problem);
        member = parsed.value;
      },
      std::string(spec.doc) + "; " + range_text(spec));
  option->type_name(std::string(type_name<T>()));
  return option;
}

/// Declares the flag of the text parameter `spec` on `command`, checked and set into `member`
/// (a std::string or a std::filesystem::path, taken as given: a relative path is the caller's).
template <class Member>
CLI::Option* add_flag(CLI::App& command, const TextSpec& spec, Member& member) {
  const std::string flag = flag_name(spec.name);
  auto* option = command.add_option_function<std::string>(
      flag,
      [spec, &member, flag](const std::string& text) {
        if (std::string why = problem(spec, text); !why.empty()) throw CLI::ValidationError(flag, why);
        member = text;
      },
      std::string(spec.doc));
  option->type_name(spec.path ? "PATH" : "TEXT");
  return option;
}

/// Declares a flag for each parameter `object` declares, parsed into its member.
template <class Object>
void add_flags(CLI::App& command, Object& object) {
  visit(object, [&](const auto& spec, auto& member) { add_flag(command, spec, member); });
}

}  // namespace ispars::params
