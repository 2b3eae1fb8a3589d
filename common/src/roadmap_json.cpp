#include "ispars/roadmap_json.hpp"

#include <nlohmann/json.hpp>

namespace ispars {
namespace {

nlohmann::json point(const Vec3& p) { return nlohmann::json::array({p.x(), p.y(), p.z()}); }

nlohmann::json graph_json(const Roadmap& g) {
  nlohmann::json vertices = nlohmann::json::array();
  nlohmann::json visible = nlohmann::json::array();
  nlohmann::json edges = nlohmann::json::array();
  for (VertexId v = 0; v < g.vertex_count(); ++v) {
    vertices.push_back(point(g.position(v)));
    visible.push_back(g.visibility_table().ids(v));
  }
  for (const RoadmapEdge& e : g.edges()) edges.push_back({e.u, e.v, e.cost});
  return {{"vertices", std::move(vertices)}, {"visible", std::move(visible)}, {"edges", std::move(edges)}};
}

}  // namespace

std::string roadmap_file_json(const std::string& scene, const Vec3& root, std::span<const Vec3> pois,
                              const Roadmap& roadmap, const Roadmap* dense) {
  nlohmann::json graphs = {{"roadmap", graph_json(roadmap)}};
  if (dense != nullptr) graphs["dense"] = graph_json(*dense);
  nlohmann::json poi_list = nlohmann::json::array();
  for (const Vec3& p : pois) poi_list.push_back(point(p));
  const nlohmann::json file = {
      {"scene", scene}, {"root", point(root)}, {"pois", std::move(poi_list)}, {"graphs", std::move(graphs)}};
  return file.dump() + "\n";
}

}  // namespace ispars
