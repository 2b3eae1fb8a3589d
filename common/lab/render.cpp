// ispars-lab render: a PNG of a scene with a roadmap file's graphs, its POIs and a tour.

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/render/scene_render.hpp"
#include "ispars/roadmap/roadmap_json.hpp"

namespace ispars::lab {
namespace {

Vec3 vec3_option(const std::vector<double>& v, const char* name) {
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw params::InputError("command line", name, "needs three finite numbers");
  }
  return {v[0], v[1], v[2]};
}

// The path a tour file says to draw: its "path" (the shortcut tour, when the tour was shortcut),
// else its walk's "positions".
std::vector<Vec3> read_tour_positions(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw params::InputError(path, "--tour", "cannot open for reading");
  nlohmann::json file;
  try {
    file = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw params::InputError(path, "json", e.what());
  }
  const char* field = file.contains("path") && file["path"].is_array() && !file["path"].empty() ? "path" : "positions";
  if (!file.contains(field) || !file[field].is_array()) {
    throw params::InputError(path, "positions",
                             "missing (write the tour with ispars-lab tour --out from a roadmap file)");
  }
  std::vector<Vec3> walk;
  for (const auto& p : file[field]) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number()) {
      throw params::InputError(path, field, "each position must be three numbers");
    }
    walk.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
  }
  return walk;
}

}  // namespace

int run_render(const RenderCommandOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  const planning::Scene scene = planning::Scene::load(options.scene);
  render::RenderRequest request;
  request.width = options.width;
  request.height = options.height;
  request.max_edges = options.max_edges;
  if (!options.eye.empty() || !options.target.empty()) {
    render::Camera camera;
    camera.eye = vec3_option(options.eye, "--eye");
    camera.target = vec3_option(options.target, "--target");
    camera.fov_degrees = options.fov;
    request.camera = camera;
  }
  request.pois = scene.pois();
  std::optional<RoadmapFileGraph> roadmap, dense;
  std::vector<EdgeEnds> roadmap_ends, dense_ends;  // what the picture draws of each file graph
  const auto ends_of = [](const InspectionGraph& g, std::vector<EdgeEnds>& out) {
    for (const RoadmapEdge& e : g.edges()) out.push_back({e.u, e.v});
    return std::span<const EdgeEnds>(out);
  };
  if (!options.roadmap.empty()) {
    roadmap = read_roadmap_file_graph(options.roadmap, "roadmap");
    request.roadmap = render::DrawnGraph{roadmap->positions, ends_of(roadmap->graph, roadmap_ends)};
    request.poi_seen.assign(scene.pois().size(), false);
    for (VertexId v = 0; v < roadmap->graph.vertex_count(); ++v) {
      for (const PoiId p : roadmap->graph.visible(v)) {
        if (p < request.poi_seen.size()) request.poi_seen[p] = true;
      }
    }
    if (options.dense) {
      dense = read_roadmap_file_graph(options.roadmap, "dense");
      request.dense = render::DrawnGraph{dense->positions, ends_of(dense->graph, dense_ends)};
    }
  } else if (options.dense) {
    throw params::InputError("command line", "--dense", "needs --roadmap (the file holds the dense graph)");
  }
  std::vector<Vec3> tour;
  if (!options.tour.empty()) tour = read_tour_positions(options.tour);
  request.tour = tour;
  const auto t1 = std::chrono::steady_clock::now();
  const render::RenderResult result = render::render_scene(scene.mesh(), request);
  const auto t2 = std::chrono::steady_clock::now();
  try {
    render::write_png(options.out, result.image);
  } catch (const std::runtime_error& e) {
    throw params::InputError(options.out, "--out", e.what());
  }
  const double load_s = std::chrono::duration<double>(t1 - t0).count();
  const double render_s = std::chrono::duration<double>(t2 - t1).count();
  const std::size_t roadmap_edges = roadmap ? roadmap->graph.edge_count() : 0;
  const std::size_t dense_edges = dense ? dense->graph.edge_count() : 0;
  const auto& c = result.camera;
  if (options.json) {
    const nlohmann::json out = {{"out", options.out},
                                {"width", options.width},
                                {"height", options.height},
                                {"eye", {c.eye.x(), c.eye.y(), c.eye.z()}},
                                {"target", {c.target.x(), c.target.y(), c.target.z()}},
                                {"roadmap_edges", roadmap_edges},
                                {"roadmap_edges_drawn", result.roadmap_edges_drawn},
                                {"dense_edges", dense_edges},
                                {"dense_edges_drawn", result.dense_edges_drawn},
                                {"tour_steps", tour.empty() ? 0 : tour.size() - 1},
                                {"load_seconds", load_s},
                                {"render_seconds", render_s}};
    std::cout << out.dump() << std::endl;
  } else {
    std::cout << fmt::format("wrote {} ({}x{}) in {:.2f} s (loading {:.2f} s); camera at ({:.1f}, {:.1f}, {:.1f})\n",
                             options.out, options.width, options.height, render_s, load_s, c.eye.x(), c.eye.y(),
                             c.eye.z());
    if (result.roadmap_edges_drawn < roadmap_edges || result.dense_edges_drawn < dense_edges) {
      std::cout << fmt::format(
          "drew an evenly spread subset: {} of {} roadmap edges, {} of {} dense edges "
          "(--max-edges {})\n",
          result.roadmap_edges_drawn, roadmap_edges, result.dense_edges_drawn, dense_edges, options.max_edges);
    }
  }
  return 0;
}

CLI::App* add_render_command(CLI::App& parent, RenderCommandOptions& options) {
  auto* cmd = parent.add_subcommand("render", "A PNG of a scene, a roadmap file's graphs, its POIs and a tour");
  cmd->add_option("scene", options.scene, "Scene YAML")->required()->check(CLI::ExistingFile);
  cmd->add_option("--roadmap", options.roadmap, "Roadmap JSON (ispars-lab build --out, ispars snapshot --out)");
  cmd->add_flag("--dense", options.dense, "Also draw the file's dense graph, faint");
  cmd->add_option("--tour", options.tour, "Tour JSON (ispars-lab tour --out)");
  cmd->add_option("--out", options.out, "The PNG file to write")->required();
  cmd->add_option("--width", options.width, "Pixels")->check(CLI::Range(16, 8192));
  cmd->add_option("--height", options.height, "Pixels")->check(CLI::Range(16, 8192));
  cmd->add_option("--eye", options.eye, "Camera position X Y Z (default: framed from the front-right)")->expected(3);
  cmd->add_option("--target", options.target, "Camera target X Y Z (with --eye)")->expected(3);
  cmd->add_option("--fov", options.fov, "Vertical field of view, degrees")->check(CLI::Range(1.0, 170.0));
  cmd->add_option("--max-edges", options.max_edges, "Edges of each graph drawn at most (an evenly spread subset)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100'000'000}));
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  return cmd;
}

}  // namespace ispars::lab
