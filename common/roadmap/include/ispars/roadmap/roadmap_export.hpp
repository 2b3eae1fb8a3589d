#pragma once
// A roadmap in the graph formats other tools read: ASCII PLY (MeshLab, CloudCompare, Open3D,
// Blender) and GraphML (networkx, Gephi, yEd, igraph). Coordinates and lengths are written as the
// shortest text that reads back to the same double.

#include <string>

#include "ispars/roadmap/roadmap.hpp"

namespace ispars {

/// PLY: a `vertex` element (x, y, z as doubles, and `pois`, how many POIs each sees) and an `edge`
/// element (vertex1, vertex2), with the POI count and the digest in a comment.
[[nodiscard]] std::string roadmap_ply(const Roadmap& roadmap);
/// GraphML: undirected; nodes n0.. with x, y, z and pois (the POI ids, space-separated), edges
/// e0.. with weight (the edge's length).
[[nodiscard]] std::string roadmap_graphml(const Roadmap& roadmap);

}  // namespace ispars
