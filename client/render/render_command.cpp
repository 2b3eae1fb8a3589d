#include "render_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "ispars/cli_app/whole_number.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/render/scene_render.hpp"

namespace ispars::cli {

CLI::App* add_render_command(CLI::App& app, RenderArgs& args) {
  auto* cmd = app.add_subcommand("render", "a PNG of the scene's roadmap as the daemon serves it, and a tour");
  cmd->add_option("scene", args.scene, "scene name")->required();
  cmd->add_option("--scene-file", args.scene_file,
                  "the scene's YAML here, for its mesh (checked against the daemon's POIs)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", args.out, "PNG file to write")->required();
  cmd->add_option("--tour", args.tour_budget, "also draw a tour the daemon searches for this many seconds")
      ->check(CLI::Range(0.001, 3600.0));
  cmd->add_option("--width", args.width, "pixels")->check(CLI::Range(16, 8192));
  cmd->add_option("--height", args.height, "pixels")->check(CLI::Range(16, 8192));
  cmd->add_option("--eye", args.eye, "camera position X Y Z (default: framed from the front-right)")->expected(3);
  cmd->add_option("--target", args.target, "camera target X Y Z (with --eye)")->expected(3);
  cmd->add_option("--max-edges", args.max_edges, "edges drawn at most (an evenly spread subset)")
      ->check(cli_app::whole_number(1, 100'000'000));
  cmd->add_option("--task", args.task, "draw this inspection task's POIs (ispars task list), and its tour with --tour");
  return cmd;
}

int render_from_daemon(client::Client& client, const RenderArgs& args) {
  planning::Scene scene = [&] {
    try {
      return planning::Scene::load(args.scene_file);
    } catch (const params::InputError& e) {
      throw CLI::ValidationError("--scene-file", e.what());
    }
  }();
  const client::Snapshot snapshot = client.snapshot(args.scene);
  // The mesh is the user's copy: it must be the daemon's scene, which its POIs tell (the
  // daemon's begin with the scene file's; its inspection tasks' follow).
  bool same = snapshot.pois.size() >= scene.pois().size();
  for (std::size_t i = 0; same && i < scene.pois().size(); ++i)
    same = (snapshot.pois[i] - scene.pois()[i]).norm() < 1e-6;
  if (!same) {
    throw CLI::ValidationError("--scene-file",
                               fmt::format("{} is not the daemon's scene '{}': its {} POIs differ from the "
                                           "daemon's {}",
                                           args.scene_file, args.scene, scene.pois().size(), snapshot.pois.size()));
  }
  std::vector<Vec3> tour;
  double tour_cost = 0.0;
  if (args.tour_budget > 0) {
    const auto reply = args.task.empty() ? client.tour(args.scene, args.tour_budget, 1, {}, {})
                                         : client.task_tour(args.scene, args.task, args.tour_budget, 1, {});
    // The flown tour: the path a robot flies (the roadmap walk when the daemon sent none).
    const client::Tour& r = reply.tour;
    const auto& drawn = r.flown_path.empty() ? r.waypoints : r.flown_path;
    for (const auto& p : drawn) tour.emplace_back(p.x(), p.y(), p.z());
    tour_cost = r.flown_path.empty() ? r.cost : r.flown_cost;
  }
  render::RenderRequest request;
  request.width = args.width;
  request.height = args.height;
  request.max_edges = args.max_edges;
  if (!args.eye.empty() || !args.target.empty()) {
    if (args.eye.size() != 3 || args.target.size() != 3) {
      throw CLI::ValidationError("--eye", "give --eye X Y Z and --target X Y Z together");
    }
    request.camera = render::Camera{Vec3(args.eye[0], args.eye[1], args.eye[2]),
                                    Vec3(args.target[0], args.target[1], args.target[2]), Vec3::UnitZ(), 45.0};
  }
  const Roadmap& g = snapshot.roadmap;
  request.roadmap = render::DrawnGraph{g.positions(), g.edge_ends()};
  // The POIs drawn: every POI the roadmap knows, or one task's (ids first .. first + count - 1).
  std::size_t first = 0, count = std::min(snapshot.pois.size(), g.poi_count());
  if (!args.task.empty()) {
    const std::vector<client::TaskEntry> tasks = client.tasks(args.scene);
    const auto task = std::find_if(tasks.begin(), tasks.end(), [&](const auto& t) { return t.name == args.task; });
    if (task == tasks.end()) {
      throw CLI::ValidationError("--task",
                                 fmt::format("scene '{}' has no task '{}' (ispars task list)", args.scene, args.task));
    }
    first = std::min<std::size_t>(task->first_poi, count);
    count = std::min<std::size_t>(task->poi_count, count - first);
  }
  request.pois = std::span<const Vec3>(snapshot.pois).subspan(first, count);
  request.poi_seen.assign(count, false);
  for (VertexId v = 0; v < g.vertex_count(); ++v) {
    for (const PoiId p : g.visibility_table().ids(v)) {
      if (p >= first && p < first + count) request.poi_seen[p - first] = true;
    }
  }
  request.tour = tour;
  render::RenderResult result;
  try {
    result = render::render_scene(scene.mesh(), request);
    render::write_png(args.out, result.image);
  } catch (const std::runtime_error& e) {
    throw CLI::ValidationError("--out", e.what());
  }
  std::cout << fmt::format("wrote {} ({}x{}): {} at version {}, {} vertices, {} of {} edges drawn{}\n", args.out,
                           args.width, args.height, args.scene, snapshot.version, g.vertex_count(),
                           result.roadmap_edges_drawn, g.edge_count(),
                           tour.empty() ? "" : fmt::format(", a tour of {:.6g}", tour_cost));
  return 0;
}

}  // namespace ispars::cli

namespace ispars::cli {
namespace {

class RenderCommand final : public cli_app::Command {
 public:
  CLI::App* add(CLI::App& app) override { return add_render_command(app, args_); }
  int run(client::Client& client) override { return render_from_daemon(client, args_); }

 private:
  RenderArgs args_;
};

}  // namespace

std::unique_ptr<cli_app::Command> make_render_command() { return std::make_unique<RenderCommand>(); }

}  // namespace ispars::cli
