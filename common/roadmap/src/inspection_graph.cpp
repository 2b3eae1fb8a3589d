#include "ispars/roadmap/inspection_graph.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "ispars/params/input_error.hpp"

namespace ispars {

InspectionGraph InspectionGraph::from_roadmap(const Roadmap& roadmap) {
  InspectionGraph g;
  g.poi_count_ = roadmap.visibility_table().poi_count();
  g.edges_.assign(roadmap.edges().begin(), roadmap.edges().end());
  g.visible_.resize(roadmap.vertex_count());
  for (VertexId v = 0; v < roadmap.vertex_count(); ++v) g.visible_[v] = roadmap.visibility_table().ids(v);
  g.finish();
  return g;
}

InspectionGraph InspectionGraph::from_edges(std::size_t vertices, std::span<const RoadmapEdge> edges,
                                            std::vector<std::vector<PoiId>> visible, std::size_t poi_count) {
  if (visible.size() != vertices) throw params::InputError("graph", "visible", "needs one POI list per vertex");
  InspectionGraph g;
  g.poi_count_ = poi_count;
  for (const RoadmapEdge& e : edges) {
    if (e.u >= vertices || e.v >= vertices) {
      throw params::InputError("graph", "edges",
                               fmt::format("edge {}-{} names a vertex beyond {}", e.u, e.v, vertices));
    }
    if (!std::isfinite(e.cost) || e.cost < 0) {
      throw params::InputError("graph", "edges", fmt::format("edge {}-{} has cost {}", e.u, e.v, e.cost));
    }
    if (e.u != e.v) g.edges_.push_back(e);
  }
  for (auto& list : visible) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    if (!list.empty() && list.back() >= poi_count) {
      throw params::InputError("graph", "visible", fmt::format("POI {} is beyond the {} POIs", list.back(), poi_count));
    }
  }
  g.visible_ = std::move(visible);
  g.finish();
  return g;
}

namespace {

// A line's whitespace-separated fields.
std::vector<std::string> fields_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string f; in >> f;) out.push_back(f);
  return out;
}

// The whole field as a number of type T, or nullopt ("0.5" is no integer, "1x" no number).
template <class T>
std::optional<T> whole(const std::string& field) {
  T value{};
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc() || end != field.data() + field.size()) return std::nullopt;
  return value;
}

}  // namespace

InspectionGraph InspectionGraph::read_iris(const std::filesystem::path& prefix, bool all_edges) {
  const std::string vertex_file = prefix.string() + "_vertex";
  const std::string edge_file = prefix.string() + "_edge";
  std::ifstream vin(vertex_file);
  if (!vin) throw params::InputError(vertex_file, "file", "cannot be read");
  std::vector<std::vector<PoiId>> visible;
  std::size_t poi_count = 0;
  std::string line;
  for (std::size_t number = 1; std::getline(vin, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> f = fields_of(line);
    const auto index = f.size() >= 3 ? whole<long long>(f[0]) : std::nullopt;
    if (!index || !whole<double>(f[1]) || !whole<double>(f[2])) {
      throw params::InputError(vertex_file, fmt::format("line {}", number),
                               "expected 'index time_vis time_build poi ...' (an integer index, two numbers)");
    }
    if (*index != static_cast<long long>(visible.size())) {
      throw params::InputError(vertex_file, fmt::format("line {}", number),
                               fmt::format("vertex index {} where {} was expected (indices are consecutive from 0)",
                                           *index, visible.size()));
    }
    std::vector<PoiId> pois;
    for (std::size_t k = 3; k < f.size(); ++k) {
      const auto p = whole<long long>(f[k]);
      if (!p) throw params::InputError(vertex_file, fmt::format("line {}", number), "a POI id is not an integer");
      if (*p < 0 || *p > 100'000'000) {
        throw params::InputError(vertex_file, fmt::format("line {}", number), fmt::format("POI id {}", *p));
      }
      pois.push_back(static_cast<PoiId>(*p));
      poi_count = std::max<std::size_t>(poi_count, static_cast<std::size_t>(*p) + 1);
    }
    visible.push_back(std::move(pois));
  }
  if (visible.empty()) throw params::InputError(vertex_file, "file", "has no vertices");
  std::ifstream ein(edge_file);
  if (!ein) throw params::InputError(edge_file, "file", "cannot be read");
  std::vector<RoadmapEdge> edges;
  for (std::size_t number = 1; std::getline(ein, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> f = fields_of(line);
    const auto u_read = f.size() == 7 ? whole<long long>(f[0]) : std::nullopt;
    const auto v_read = f.size() == 7 ? whole<long long>(f[1]) : std::nullopt;
    const auto checked = f.size() == 7 ? whole<int>(f[2]) : std::nullopt;
    const auto valid_read = f.size() == 7 ? whole<int>(f[3]) : std::nullopt;
    const auto cost_read = f.size() == 7 ? whole<double>(f[6]) : std::nullopt;
    if (!u_read || !v_read || !checked || !valid_read || !whole<double>(f[4]) || !whole<double>(f[5]) || !cost_read) {
      throw params::InputError(
          edge_file, fmt::format("line {}", number),
          "expected 'source target checked valid time_fk time_cd cost' (four integers, three numbers)");
    }
    const long long u = *u_read, v = *v_read;
    const int valid = *valid_read;
    const double cost = *cost_read;
    if (u < 0 || v < 0 || u >= static_cast<long long>(visible.size()) || v >= static_cast<long long>(visible.size())) {
      throw params::InputError(edge_file, fmt::format("line {}", number),
                               fmt::format("edge {}-{} names a vertex outside 0..{}", u, v, visible.size() - 1));
    }
    if (!std::isfinite(cost) || cost < 0) {
      throw params::InputError(edge_file, fmt::format("line {}", number),
                               fmt::format("cost {} is not a finite length", cost));
    }
    if (valid == 0 && !all_edges) continue;
    edges.push_back({static_cast<VertexId>(u), static_cast<VertexId>(v), cost});
  }
  const std::size_t vertices = visible.size();
  return from_edges(vertices, edges, std::move(visible), poi_count);
}

void InspectionGraph::finish() {
  offsets_.assign(visible_.size() + 1, 0);
  for (const RoadmapEdge& e : edges_) {
    ++offsets_[e.u + 1];
    ++offsets_[e.v + 1];
  }
  for (std::size_t i = 1; i < offsets_.size(); ++i) offsets_[i] += offsets_[i - 1];
  neighbors_.assign(offsets_.back(), {});
  std::vector<std::size_t> at(offsets_.begin(), offsets_.end() - 1);
  for (const RoadmapEdge& e : edges_) {
    neighbors_[at[e.u]++] = {e.v, e.cost};
    neighbors_[at[e.v]++] = {e.u, e.cost};
  }
}

double InspectionGraph::edge_cost(VertexId u, VertexId v) const {
  double best = -1.0;
  for (const Neighbor& n : neighbors(u)) {
    if (n.vertex == v && (best < 0 || n.cost < best)) best = n.cost;
  }
  return best;
}

std::vector<VertexId> InspectionGraph::component_of(VertexId v) const {
  std::vector<char> seen(vertex_count(), 0);
  std::vector<VertexId> stack{v}, out;
  seen[v] = 1;
  while (!stack.empty()) {
    const VertexId x = stack.back();
    stack.pop_back();
    out.push_back(x);
    for (const Neighbor& n : neighbors(x)) {
      if (!seen[n.vertex]) {
        seen[n.vertex] = 1;
        stack.push_back(n.vertex);
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ispars
