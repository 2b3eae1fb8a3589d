#pragma once
// The roadmap file format shared by `ispars-lab build --out`, `ispars watch --dump` and
// `ispars snapshot --out`: the scene's root and POIs, and each graph's vertices, visible POIs
// and edges, as JSON.

#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "ispars/roadmap/inspection_graph.hpp"
#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// The JSON text (one line) of a roadmap file. `dense` may be nullptr.
[[nodiscard]] std::string roadmap_file_json(const std::string& scene, const Vec3& root, std::span<const Vec3> pois,
                                            const Roadmap& roadmap, const Roadmap* dense);

/// One graph of a roadmap file ("roadmap" or "dense") as a tour-planning graph, with its vertex
/// positions. Throws InputError naming the file and the field when the file does not parse or
/// the graph is missing or inconsistent.
struct RoadmapFileGraph {
  InspectionGraph graph;
  std::vector<Vec3> positions;
};
[[nodiscard]] RoadmapFileGraph read_roadmap_file_graph(const std::filesystem::path& path, const std::string& which);

}  // namespace ispars
