// `ispars-render`: `ispars render` as a program of its own, the one client program that links the
// renderer (the scene's mesh through assimp, rays through Embree). `ispars render ARGS` runs it
// with the same arguments: `ispars-render [connection flags] render SCENE ...`.

#include "ispars/cli_app/cli_app.hpp"
#include "render_command.hpp"

int main(int argc, char** argv) {
  using namespace ispars::cli;
  std::vector<std::unique_ptr<ispars::cli_app::Command>> commands;
  commands.push_back(make_render_command());
  return ispars::cli_app::run_cli(argc, argv,
                                  "ispars-render: a PNG of a scene's roadmap as an isparsd daemon serves it", commands);
}
