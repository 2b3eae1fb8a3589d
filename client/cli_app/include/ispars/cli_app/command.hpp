#pragma once
// A subcommand of a client program (`ispars`, `ispars-render`): it declares its arguments on the
// app, and, when it is the one the user chose, runs with a connected client and returns the exit
// code. Client errors propagate to run_cli (cli_app.hpp), which maps them to exit codes.

#include <CLI/CLI.hpp>

#include <optional>

#include "ispars/client/client.hpp"

namespace ispars::cli_app {

/// One subcommand of a client program.
class Command {
 public:
  virtual ~Command() = default;
  /// Declares the subcommand and its arguments on `app`; returns it (parsed() says it was chosen).
  virtual CLI::App* add(CLI::App& app) = 0;
  /// Called after parsing, before a client exists: throws CLI::ValidationError on bad arguments.
  virtual void check() {}
  /// Does it; the process's exit code.
  virtual int run(client::Client& client) = 0;
  /// A command another program does (delegate_command.cpp) replaces this process with it, given
  /// the same arguments, before any client connects; returns only when it could not.
  virtual std::optional<int> run_elsewhere(int /*argc*/, char** /*argv*/) { return std::nullopt; }
};

}  // namespace ispars::cli_app
