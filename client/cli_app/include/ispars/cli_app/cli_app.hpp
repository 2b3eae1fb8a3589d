#pragma once
// What every `ispars` program shares: the connection's flags (or ISPARS_* variables), parsing,
// and the exit codes. `ispars` and `ispars-render` are this with different subcommands.

#include <memory>
#include <vector>

#include "ispars/cli_app/command.hpp"

namespace ispars::cli_app {

/// Parses argv against `commands` and the connection's flags, connects, and runs the chosen
/// command. Exit codes: 0 done, 1 refused or failed (a rejected or forbidden request, a failed
/// job, an invalid tour), 2 bad arguments, 3 no daemon or no reply. `title` heads --help.
int run_cli(int argc, char** argv, const char* title, const std::vector<std::unique_ptr<Command>>& commands);

}  // namespace ispars::cli_app
