#pragma once
// Every setting of isparsd declared once: its YAML key (the flag is the key with dashes, plus an
// older alias for two), its field in DaemonConfig, its bounds and its doc. The config file's
// reader, the command-line flags, the checks and `isparsd --help` all walk this list
// (visit_settings), so a setting cannot be read one way and checked another. Each value is
// checked where it arrives (a file's key, a flag), naming that key or flag.

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "daemon_config.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/wire/participant_options.hpp"

namespace ispars::server {

/// What a value of a setting must be besides its type and bounds: an error text, or empty.
template <class T>
using SettingRule = std::string (*)(const T&);

/// An integer setting: inclusive bounds, checked before the value is narrowed to the field.
template <class T>
struct IntegerSetting {
  T DaemonConfig::*field;
  std::string_view key;
  std::string_view doc;
  std::int64_t min = 0;
  std::int64_t max = 0;
  SettingRule<T> rule = nullptr;  ///< Checked after the bounds, on the narrowed value.
  std::string_view alias = {};    ///< An older flag, still accepted ("--compact-every").
  bool on_sighup = false;         ///< A running daemon takes a change on SIGHUP (else at a restart).
};

/// A text setting, at most `max_length` characters; a path is resolved against the config
/// file's directory when `path` is set.
template <class T>  // std::string or std::filesystem::path
struct TextSetting {
  T DaemonConfig::*field;
  std::string_view key;
  std::string_view doc;
  std::size_t max_length = 4096;
  bool path = false;
  SettingRule<T> rule = nullptr;
  bool on_sighup = false;  ///< A running daemon takes a change on SIGHUP (else at a restart).
};

/// A list of scene names, appended to by each flag.
struct ListSetting {
  std::vector<std::string> DaemonConfig::*field;
  std::string_view key;
  std::string_view doc;
  std::size_t max_items = 1024;
  std::string_view alias = {};
  bool on_sighup = false;
};

/// An ADDRESS:PORT to listen on, or none.
struct AddressSetting {
  std::optional<ListenAddress> DaemonConfig::*field;
  std::string_view key;
  std::string_view doc;
  bool on_sighup = false;
};

std::string log_level_rule(const std::string& level);
std::string log_file_rule(const std::filesystem::path& file);
std::string memory_budget_rule(const std::uint64_t& mib);

/// Calls `visit` with each setting's declaration, in the order `isparsd --help` lists them.
template <class Visitor>
void visit_settings(Visitor&& visit) {
  using C = DaemonConfig;
  visit(TextSetting<std::filesystem::path>{&C::data_dir, "data_dir", "where roadmaps are stored", 4096, true});
  visit(TextSetting<std::filesystem::path>{&C::scene_dir, "scene_dir", "the only directory scenes are loaded from",
                                           4096, true});
  visit(IntegerSetting<int>{&C::domain, "domain", "DDS domain id; without a config file $ISPARS_DOMAIN is the default",
                            0, 232});
  visit(IntegerSetting<unsigned>{&C::workers, "workers", "build worker threads", 1, 64});
  visit(IntegerSetting<unsigned>{&C::build_threads, "build_threads",
                                 "threads each build uses (the roadmap is the same for any count)", 1, 64});
  visit(TextSetting<std::string>{&C::profile_file, "profile_file",
                                 "Fast DDS XML profiles file (default: built-in localhost only)", 4096, true});
  visit(TextSetting<std::string>{&C::profile_name, "profile_name", "participant profile in the profiles file", 256});
  visit(TextSetting<std::string>{&C::security, "security",
                                 "DDS Security identity directory (deploy/security/make-keystore.sh); default: none",
                                 4096, true});
  visit(IntegerSetting<unsigned>{&C::lease_s, "lease_s",
                                 "seconds a peer waits on this daemon's silence before dropping it, with the "
                                 "built-in settings (0: 3, or 20 under DDS Security; a profiles file sets its own)",
                                 0, wire::kMaxLeaseSeconds});
  visit(TextSetting<std::string>{&C::log_level, "log_level", "trace, debug, info, warn, error, critical or off", 16,
                                 false, &log_level_rule, true});
  visit(TextSetting<std::string>{&C::server_id, "server_id", "this daemon's unique id on the domain (default HOST-PID)",
                                 64});
  visit(IntegerSetting<std::uint64_t>{&C::max_samples, "max_samples", "largest build or extend a request may ask for",
                                      1, static_cast<std::int64_t>(kSamples.max)});
  visit(IntegerSetting<std::size_t>{&C::snapshot_compact_every, "snapshot_compact_every",
                                    "journal commits between compacted snapshots", 1, 1'000'000'000, nullptr,
                                    "compact-every"});
  visit(ListSetting{&C::preload, "preload", "scenes to load at start (stored roadmaps load anyway)", 1024, "load"});
  visit(IntegerSetting<std::size_t>{&C::request_queue, "request_queue",
                                    "requests each lane (quick, slow) holds waiting before it answers busy", 1,
                                    100'000});
  visit(IntegerSetting<std::uint64_t>{&C::memory_budget_mb, "memory_budget_mb",
                                      "MiB all loaded roadmaps may be expected to hold, 0 for half of RAM; builds "
                                      "past it are refused",
                                      0, std::int64_t{1} << 30, &memory_budget_rule});
  visit(IntegerSetting<std::uint32_t>{&C::discovery_wait_ms, "discovery_wait_ms",
                                      "how long to listen for the other daemons before claiming scenes", 100, 60'000});
  visit(TextSetting<std::filesystem::path>{&C::log_file, "log_file",
                                           "log to this file, rotated by size and reopened on SIGHUP (default: stdout)",
                                           4096, true, &log_file_rule, true});
  visit(IntegerSetting<std::uint64_t>{
      &C::log_file_mb, "log_file_mb", "MiB a log file reaches before it is rotated", 1, 100'000, nullptr, {}, true});
  visit(AddressSetting{&C::metrics, "metrics",
                       "ADDRESS:PORT serving /metrics (Prometheus) and /healthz over HTTP, e.g. 127.0.0.1:9464 "
                       "(default: none)"});
}

/// The keys of the settings that differ between `running` and `fresh` and that a running daemon
/// takes only at a restart (each one not declared on_sighup), in declaration order. A fresh
/// config without a server_id asks for the default the running one already holds.
[[nodiscard]] std::vector<std::string> changed_needing_restart(const DaemonConfig& running, DaemonConfig fresh);

/// The flag of a setting: "--" and its key with dashes ("data_dir": "--data-dir").
[[nodiscard]] std::string flag_of(std::string_view key);

/// `config` as a config file (`isparsd --print-config`): every setting, paths made absolute, an
/// unset listen address left out. Reading it back gives the same config.
[[nodiscard]] std::string to_yaml(const DaemonConfig& config);

/// `value` for the setting `s`, or InputError naming `source` and `field` (a key or a flag).
template <class T>
T checked_integer(const IntegerSetting<T>& s, std::int64_t value, const std::string& source, const std::string& field) {
  if (value < s.min || value > s.max) {
    throw InputError(source, field, fmt::format("must be in {}..{}, got {}", s.min, s.max, value));
  }
  const T typed = static_cast<T>(value);
  if (s.rule != nullptr) {
    if (std::string why = s.rule(typed); !why.empty()) throw InputError(source, field, std::move(why));
  }
  return typed;
}

/// `text` for the setting `s` (a path resolved against `base` when it is relative), or
/// InputError naming `source` and `field`.
template <class T>
T checked_text(const TextSetting<T>& s, const std::string& text, const std::filesystem::path& base,
               const std::string& source, const std::string& field) {
  if (text.size() > s.max_length) {
    throw InputError(source, field, fmt::format("is longer than {} characters", s.max_length));
  }
  T typed{text};
  if (s.path && !text.empty()) {
    const std::filesystem::path given(text);
    const std::filesystem::path resolved = given.is_absolute() ? given : base / given;
    if constexpr (std::is_same_v<T, std::string>) {
      typed = resolved.string();
    } else {
      typed = resolved;
    }
  }
  if (s.rule != nullptr) {
    if (std::string why = s.rule(typed); !why.empty()) throw InputError(source, field, std::move(why));
  }
  return typed;
}

/// `items` for the setting `s`, or InputError naming `source` and `field`.
inline std::vector<std::string> checked_list(const ListSetting& s, std::vector<std::string> items,
                                             const std::string& source, const std::string& field) {
  if (items.size() > s.max_items) throw InputError(source, field, fmt::format("has more than {} items", s.max_items));
  for (const std::string& item : items) {
    if (item.size() > 256) throw InputError(source, field, "has an item longer than 256 characters");
  }
  return items;
}

}  // namespace ispars::server
