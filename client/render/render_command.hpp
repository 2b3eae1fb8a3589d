#pragma once
// `ispars render`: a PNG of a scene's roadmap as the daemon serves it (its snapshot), over the
// scene's mesh loaded from the user's copy of the scene file, with a tour the daemon searches;
// with --task, an inspection task's POIs and its tour.

#include <CLI/CLI.hpp>

#include <memory>
#include <string>
#include <vector>

#include "ispars/cli_app/command.hpp"
#include "ispars/client/client.hpp"

namespace ispars::cli {

/// The command's arguments, as parsed.
struct RenderArgs {
  std::string scene;         ///< The scene's name on the daemon.
  std::string scene_file;    ///< Its YAML here (for the mesh); checked against the daemon's POIs.
  std::string out;           ///< The PNG to write.
  double tour_budget = 0.0;  ///< Seconds of tour search by the daemon (0: no tour).
  int width = 1600;
  int height = 1200;
  std::vector<double> eye, target;
  std::size_t max_edges = 2'000'000;
  std::string task;  ///< Not empty: draw this inspection task's POIs (and tour) only.
};

/// `render`, the one command of ispars-render.
std::unique_ptr<cli_app::Command> make_render_command();

/// Declares `render` on `app`, parsing into `args`.
CLI::App* add_render_command(CLI::App& app, RenderArgs& args);

/// Fetches the snapshot (and a tour), renders and writes the PNG; prints one line. Throws
/// CLI::ValidationError naming the option when the scene file does not match the daemon's scene
/// or the file cannot be written, and client::ClientError as every request does.
int render_from_daemon(client::Client& client, const RenderArgs& args);

}  // namespace ispars::cli
