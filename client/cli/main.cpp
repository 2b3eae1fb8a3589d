// `ispars`: the command-line client of isparsd. Each subcommand lives in a file of its own
// (commands.hpp); the connection's flags and the exit codes in cli_app.cpp. It links the client
// library only: `render` runs `ispars-render` (render_main.cpp).

#include "commands.hpp"
#include "ispars/cli_app/cli_app.hpp"

int main(int argc, char** argv) {
  using namespace ispars::cli;
  std::vector<std::unique_ptr<ispars::cli_app::Command>> commands;
  for (auto* make :
       {make_scenes_command, make_build_command, make_extend_command, make_cancel_command, make_stats_command,
        make_drop_command, make_verify_command, make_path_command, make_watch_command, make_tour_command,
        make_snapshot_command, make_record_command, make_task_command, make_render_delegate}) {
    commands.push_back(make());
  }
  return ispars::cli_app::run_cli(argc, argv, "ispars: client of the isparsd roadmap service", commands);
}
