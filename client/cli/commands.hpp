#pragma once
// The subcommands of `ispars`, one file each (the Command interface: ispars/cli_app/command.hpp).

#include <memory>

#include "ispars/cli_app/command.hpp"

namespace ispars::cli {

std::unique_ptr<cli_app::Command> make_scenes_command();    // scenes list | load | unload
std::unique_ptr<cli_app::Command> make_build_command();     // build
std::unique_ptr<cli_app::Command> make_extend_command();    // extend
std::unique_ptr<cli_app::Command> make_cancel_command();    // cancel
std::unique_ptr<cli_app::Command> make_stats_command();     // stats
std::unique_ptr<cli_app::Command> make_drop_command();      // drop
std::unique_ptr<cli_app::Command> make_verify_command();    // verify
std::unique_ptr<cli_app::Command> make_path_command();      // path
std::unique_ptr<cli_app::Command> make_watch_command();     // watch
std::unique_ptr<cli_app::Command> make_tour_command();      // tour
std::unique_ptr<cli_app::Command> make_snapshot_command();  // snapshot
std::unique_ptr<cli_app::Command> make_record_command();    // record
std::unique_ptr<cli_app::Command> make_task_command();      // task add | list
std::unique_ptr<cli_app::Command> make_render_delegate();   // render in ispars: runs ispars-render

}  // namespace ispars::cli
