#include "ispars/roadmap/roadmap_json.hpp"

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <cstdint>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>

#include "ispars/params/input_error.hpp"

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

namespace {

// A vertex or POI id that is not a whole number in range (1.5, -1, 2^40): the file is malformed.
struct BadId : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `x` as an id; `what` (with `{}` for `index`) names it in the error, formatted only then.
std::uint32_t id_of(const nlohmann::json& x, const char* what, std::size_t index) {
  if (!x.is_number_unsigned() || x.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max()) {
    throw BadId(fmt::format("{} is {}, not a whole number in 0..{}", fmt::format(fmt::runtime(what), index), x.dump(),
                            std::numeric_limits<std::uint32_t>::max()));
  }
  return static_cast<std::uint32_t>(x.get<std::uint64_t>());
}

}  // namespace

RoadmapFileGraph read_roadmap_file_graph(const std::filesystem::path& path, const std::string& which) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw params::InputError(file, "file", "cannot be read");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw params::InputError(file, "json", e.what());
  }
  const std::string field = "graphs." + which;
  if (!j.is_object() || !j.contains("graphs") || !j["graphs"].is_object() || !j["graphs"].contains(which)) {
    throw params::InputError(file, field, "missing (the file has no such graph)");
  }
  try {
    const nlohmann::json& g = j["graphs"][which];
    const auto& vertices = g.at("vertices");
    const auto& visible = g.at("visible");
    const auto& edges = g.at("edges");
    if (vertices.size() != visible.size()) throw params::InputError(file, "visible", "needs one POI list per vertex");
    RoadmapFileGraph out;
    std::vector<std::vector<PoiId>> lists;
    for (const auto& v : vertices)
      out.positions.emplace_back(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>());
    for (std::size_t v = 0; v < visible.size(); ++v) {
      std::vector<PoiId>& list = lists.emplace_back();
      for (const auto& p : visible[v].get_ref<const nlohmann::json::array_t&>()) {
        list.push_back(id_of(p, "a POI id of vertex {}", v));
      }
    }
    std::vector<RoadmapEdge> edge_list;
    for (std::size_t k = 0; k < edges.size(); ++k) {
      const auto& e = edges[k];
      edge_list.push_back({id_of(e.at(0), "edge {}'s first vertex", k), id_of(e.at(1), "edge {}'s second vertex", k),
                           e.at(2).get<double>()});
    }
    const std::size_t pois = j.contains("pois") ? j["pois"].size() : 0;
    out.graph = InspectionGraph::from_edges(vertices.size(), edge_list, std::move(lists), pois);
    return out;
  } catch (const nlohmann::json::exception& e) {
    throw params::InputError(file, field, std::string("malformed: ") + e.what());
  } catch (const BadId& e) {
    throw params::InputError(file, field, std::string("malformed: ") + e.what());
  } catch (const params::InputError& e) {
    throw params::InputError(file, field + "." + e.field(), e.problem());
  }
}

}  // namespace ispars
