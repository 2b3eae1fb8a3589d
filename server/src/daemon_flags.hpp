#pragma once
// isparsd's command-line flags: one per declared setting (daemon_settings.hpp), named after its
// key, with its bounds and default in the help, applied over the config file's values and checked
// as they are applied, naming the flag.

#include <CLI/CLI.hpp>

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "daemon_config.hpp"

namespace ispars::server {

/// The flags of every setting, bound to a CLI11 app.
class DaemonFlags {
 public:
  /// Adds one option per setting to `app` (which must outlive this object's use).
  explicit DaemonFlags(CLI::App& app);
  DaemonFlags(const DaemonFlags&) = delete;
  DaemonFlags& operator=(const DaemonFlags&) = delete;

  /// Writes every flag given over `config`; a list flag appends. Throws InputError naming the flag.
  void apply(DaemonConfig& config) const;

 private:
  struct Staged {  // what CLI11 parsed for one setting (an integer as text: converted here)
    std::optional<std::string> text;
    std::vector<std::string> list;
  };
  std::deque<Staged> staged_;  // a deque: CLI11 holds each element's address
  std::vector<std::function<void(DaemonConfig&)>> appliers_;
};

}  // namespace ispars::server
