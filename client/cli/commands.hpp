#pragma once
// The subcommands of `ispars`, one file each: a command declares its arguments on the app, and,
// when it is the one the user chose, runs with a connected client and returns the exit code.
// Client errors propagate to main, which maps them to exit codes.

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <vector>

#include "ispars/client/client.hpp"

namespace ispars::cli {

/// One `ispars` subcommand.
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

std::unique_ptr<Command> make_scenes_command();    // scenes list | load | unload
std::unique_ptr<Command> make_build_command();     // build
std::unique_ptr<Command> make_extend_command();    // extend
std::unique_ptr<Command> make_cancel_command();    // cancel
std::unique_ptr<Command> make_stats_command();     // stats
std::unique_ptr<Command> make_drop_command();      // drop
std::unique_ptr<Command> make_verify_command();    // verify
std::unique_ptr<Command> make_path_command();      // path
std::unique_ptr<Command> make_watch_command();     // watch
std::unique_ptr<Command> make_tour_command();      // tour
std::unique_ptr<Command> make_snapshot_command();  // snapshot
std::unique_ptr<Command> make_task_command();      // task add | list
std::unique_ptr<Command> make_render_command();    // render, in ispars-render
std::unique_ptr<Command> make_render_delegate();   // render in ispars: runs ispars-render


}  // namespace ispars::cli
