// `ispars snapshot`: the whole roadmap of a scene, written as the roadmap file JSON, or as PLY or
// GraphML for other tools (--format, or the file's extension: .ply, .graphml).

#include <fmt/format.h>

#include <iostream>

#include "commands.hpp"
#include "ispars/cli_app/cli_output.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/roadmap/roadmap_export.hpp"
#include "ispars/roadmap/roadmap_json.hpp"

namespace ispars::cli {
namespace {

class SnapshotCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override {
    auto* cmd = app.add_subcommand("snapshot", "fetch the whole roadmap");
    cmd->add_option("scene", scene_, "scene name")->required();
    cmd->add_option("--out", out_, "file to write")->required();
    cmd->add_option("--format", format_, "json (the roadmap file), ply or graphml (default: from --out's extension)")
        ->check(CLI::IsMember({"json", "ply", "graphml"}));
    return cmd;
  }
  int run(client::Client& client) override {
    const std::string format = !format_.empty()             ? format_
                               : out_.ends_with(".ply")     ? "ply"
                               : out_.ends_with(".graphml") ? "graphml"
                                                            : "json";
    const client::Snapshot s = client.snapshot(scene_);
    cli_app::write_text(out_, format == "ply"       ? roadmap_ply(s.roadmap)
                              : format == "graphml" ? roadmap_graphml(s.roadmap)
                                                    : roadmap_file_json(scene_, s.root, s.pois, s.roadmap, nullptr));
    std::cout << fmt::format("wrote {} at version {} ({} vertices, {} edges, digest {:016x}) to {}\n", scene_,
                             s.version, s.roadmap.vertex_count(), s.roadmap.edge_count(), roadmap_digest(s.roadmap),
                             out_);
    return 0;
  }

 private:
  std::string scene_, out_, format_;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_snapshot_command() { return std::make_unique<SnapshotCommand>(); }

}  // namespace ispars::cli
