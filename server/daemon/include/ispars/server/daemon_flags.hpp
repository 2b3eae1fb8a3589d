#pragma once
// isparsd's command-line flags: one per declared setting (DaemonConfig::describe), named after
// its key, with its range and default in the help, applied over the config file's values and
// checked as they are applied, naming the flag.

#include <CLI/CLI.hpp>

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "ispars/server/daemon_config.hpp"

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
  struct Staged {  // what CLI11 parsed for one setting (a number as text: converted here)
    std::optional<std::string> text;
    std::vector<std::string> list;
    bool on = false;  // a switch
  };
  std::deque<Staged> staged_;  // one per setting, in declaration order; a deque: CLI11 holds each address
};

}  // namespace ispars::server
