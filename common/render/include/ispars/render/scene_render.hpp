#pragma once
// Pictures of a scene: its mesh shaded by ray casting (Embree), its POIs (seen and unseen), a
// roadmap's edges and vertices (optionally its dense pair's edges, faint) and a tour, drawn over
// the mesh with a depth test, so what the structure hides is drawn faded.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"
#include "ispars/roadmap/vec.hpp"
#include "ispars/scene_files/triangle_mesh.hpp"

namespace ispars::render {

/// A pinhole camera: where it is, what it looks at, which way is up, and its vertical field of view.
struct Camera {
  Vec3 eye = Vec3(30, -40, 25);
  Vec3 target = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double fov_degrees = 45.0;
};

/// The camera that frames a box from the front-right, above, with all of it in view.
[[nodiscard]] Camera framing_camera(const Aabb& box, double aspect);

/// An RGB picture, rows top to bottom, 3 bytes a pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;
  [[nodiscard]] const std::uint8_t* pixel(int x, int y) const {
    return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  }
};

/// The edges of a graph to draw, by vertex position.
struct DrawnGraph {
  std::span<const Vec3> positions;
  std::span<const EdgeEnds> edges;
};

/// What a picture shows. Sizes are bounded: 16..8192 pixels a side.
struct RenderRequest {
  int width = 1600;
  int height = 1200;
  std::optional<Camera> camera;  ///< Default: framing_camera of the mesh and the tour.
  std::span<const Vec3> pois;
  std::vector<bool> poi_seen;         ///< Per POI: green seen, red unseen (empty: all purple, unknown).
  std::optional<DrawnGraph> roadmap;  ///< Drawn blue, with its vertices.
  std::optional<DrawnGraph> dense;    ///< Drawn faint grey, under the roadmap.
  std::span<const Vec3> tour;         ///< A closed walk's positions, drawn thick orange.
  std::size_t max_edges = 2'000'000;  ///< At most this many edges of each graph are drawn.
  int threads = 0;                    ///< Ray-casting threads (0: every core).
};

/// What render_scene drew.
struct RenderResult {
  Image image;
  Camera camera;
  std::size_t roadmap_edges_drawn = 0;
  std::size_t dense_edges_drawn = 0;  ///< Fewer than the graph's when max_edges cut it (a subset, evenly spread).
};

/// Renders `mesh` and what `request` adds to it. Throws InputError on a size out of range.
[[nodiscard]] RenderResult render_scene(const scene_files::TriangleMesh& mesh, const RenderRequest& request);

/// Writes a PNG file (libpng). Throws std::runtime_error naming the path on failure.
void write_png(const std::string& path, const Image& image);
/// Reads an 8-bit RGB or RGBA PNG file (for tests and tools). Throws std::runtime_error on failure.
[[nodiscard]] Image read_png(const std::string& path);

}  // namespace ispars::render
