#include "daemon_flags.hpp"

#include <fmt/format.h>

#include <charconv>
#include <type_traits>

#include "daemon_settings.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::server {
namespace {

constexpr const char* kCommandLine = "command line";

template <class S>
std::string names_of(const S& s) {
  std::string names = flag_of(s.key);
  if constexpr (requires { s.alias; }) {
    if (!s.alias.empty()) names += "," + flag_of(s.alias);
  }
  return names;
}

// `text` as a whole number, or InputError naming `flag` and the setting's bounds.
template <class S>
std::int64_t whole_number(const std::string& text, const S& s, const std::string& flag) {
  std::int64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc() || at != end) {
    throw InputError(kCommandLine, flag,
                     fmt::format("'{}' is not a whole number in {}..{}", text.substr(0, 32), s.min, s.max));
  }
  return value;
}

}  // namespace

DaemonFlags::DaemonFlags(CLI::App& app) {
  const DaemonConfig defaults;
  visit_settings([&](const auto& s) {
    using S = std::decay_t<decltype(s)>;
    Staged& staged = staged_.emplace_back();
    const std::string names = names_of(s);
    const std::string flag = flag_of(s.key);
    if constexpr (requires { s.min; }) {  // an IntegerSetting
      // Read as text and converted here: CLI11 saturates a number past 64 bits.
      app.add_option(names, staged.text, fmt::format("{} ({}..{}, default {})", s.doc, s.min, s.max, defaults.*s.field))
          ->type_name("INT");
      appliers_.push_back([s, &staged, flag](DaemonConfig& c) {
        if (staged.text) c.*s.field = checked_integer(s, whole_number(*staged.text, s, flag), kCommandLine, flag);
      });
    } else if constexpr (requires { s.max_length; }) {  // a TextSetting
      app.add_option(names, staged.text, std::string(s.doc));
      appliers_.push_back([s, &staged, flag](DaemonConfig& c) {
        if (staged.text) c.*s.field = checked_text(s, *staged.text, {}, kCommandLine, flag);
      });
    } else if constexpr (std::is_same_v<S, ListSetting>) {
      app.add_option(names, staged.list, std::string(s.doc));
      appliers_.push_back([s, &staged, flag](DaemonConfig& c) {
        std::vector<std::string> all = c.*s.field;
        all.insert(all.end(), staged.list.begin(), staged.list.end());
        c.*s.field = checked_list(s, std::move(all), kCommandLine, flag);
      });
    } else {
      static_assert(std::is_same_v<S, AddressSetting>);
      app.add_option(names, staged.text, std::string(s.doc));
      appliers_.push_back([s, &staged, flag](DaemonConfig& c) {
        if (staged.text) c.*s.field = parse_listen_address(*staged.text, kCommandLine, flag);
      });
    }
  });
}

void DaemonFlags::apply(DaemonConfig& config) const {
  for (const auto& apply_one : appliers_) apply_one(config);
}

}  // namespace ispars::server
