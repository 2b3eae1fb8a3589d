#include "ispars/server/daemon_flags.hpp"

#include <fmt/format.h>

#include <type_traits>

#include "ispars/params/fields.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/server/daemon_settings.hpp"

namespace ispars::server {
namespace {

constexpr const char* kCommandLine = "command line";

template <class S>
std::string names_of(const S& s) {
  std::string names = params::flag_name(s.name);
  if constexpr (requires { s.alias; }) {
    if (!s.alias.empty()) names += "," + params::flag_name(s.alias);
  }
  return names;
}

}  // namespace

DaemonFlags::DaemonFlags(CLI::App& app) {
  const DaemonConfig defaults;
  params::visit(defaults, [&](const auto& s, const auto& fallback) {
    using S = std::decay_t<decltype(s)>;
    Staged& staged = staged_.emplace_back();
    const std::string names = names_of(s);
    if constexpr (std::is_same_v<S, params::Spec<bool>>) {  // a switch: on when given
      app.add_flag(names, staged.on, std::string(s.doc));
    } else if constexpr (requires {
                           s.min;
                         }) {  // a number: read as text and checked here (CLI11 saturates past 64 bits)
      using T = params::value_type_of<decltype(fallback)>;
      app.add_option(names, staged.text, fmt::format("{}; {} (default {})", s.doc, params::range_text(s), fallback))
          ->type_name(std::string(params::type_name<T>()));
    } else if constexpr (std::is_same_v<S, params::ListSpec>) {
      app.add_option(names, staged.list, std::string(s.doc));
    } else {
      app.add_option(names, staged.text, std::string(s.doc));
    }
  });
}

void DaemonFlags::apply(DaemonConfig& config) const {
  std::size_t i = 0;
  params::visit(config, [&](const auto& s, auto& member) {
    using S = std::decay_t<decltype(s)>;
    const Staged& staged = staged_[i++];
    const std::string flag = params::flag_name(s.name);
    if constexpr (std::is_same_v<S, params::ListSpec>) {
      std::vector<std::string> all = member;  // a list flag appends to the file's
      all.insert(all.end(), staged.list.begin(), staged.list.end());
      member = checked_list(s, std::move(all), kCommandLine, flag);
      return;
    } else if constexpr (std::is_same_v<S, params::Spec<bool>>) {
      if (staged.on) member = true;  // a switch turns on what the file left off, never off
    } else {
      if (!staged.text) return;
      if constexpr (requires { s.min; }) {
        member = checked_number(s, *staged.text, kCommandLine, flag);
      } else if constexpr (std::is_same_v<S, params::TextSpec>) {
        member = checked_text(s, *staged.text, {}, kCommandLine, flag);  // a flag's path is the caller's, as given
      } else {
        static_assert(std::is_same_v<S, AddressSpec>);
        member = parse_listen_address(*staged.text, kCommandLine, flag);
      }
    }
  });
}

}  // namespace ispars::server
