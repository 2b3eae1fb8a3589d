#include "ispars/planning/tour/tour_corridor.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include "ispars/planning/geometry/point_grid.hpp"
#include "ispars/scene_files/random.hpp"

namespace ispars::planning {
namespace {

double distance_to_segment(const Vec3& q, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (q - (a + t * ab)).norm();
}

// The capsules of radius r around the path's segments: a uniform draw over their union.
class Tube {
 public:
  Tube(std::span<const Vec3> stops, double radius) : stops_(stops), r_(radius) {
    double total = 0.0;
    for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
      const double length = (stops[i + 1] - stops[i]).norm();
      total += std::numbers::pi * r_ * r_ * length + 4.0 / 3.0 * std::numbers::pi * r_ * r_ * r_;
      cumulative_.push_back(total);
    }
  }
  /// The capsules' volumes summed (the union's, counting overlaps as often as they occur).
  [[nodiscard]] double capsule_volume() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }

  /// A point uniform over the union, or nothing when this draw is rejected: a capsule is chosen by
  /// volume, a point uniform in it, kept with probability 1 / (capsules containing it).
  [[nodiscard]] std::optional<Vec3> draw(scene_files::Rng& rng) const {
    const double at = rng.uniform01() * capsule_volume();
    const auto i =
        static_cast<std::size_t>(std::upper_bound(cumulative_.begin(), cumulative_.end(), at) - cumulative_.begin());
    const std::size_t k = std::min(i, cumulative_.size() - 1);
    const Vec3 q = in_capsule(stops_[k], stops_[k + 1], rng);
    std::size_t containing = 0;
    for (std::size_t j = 0; j + 1 < stops_.size(); ++j) {
      if (distance_to_segment(q, stops_[j], stops_[j + 1]) <= r_) ++containing;
    }
    if (containing > 1 && rng.uniform01() * static_cast<double>(containing) >= 1.0) return std::nullopt;
    return q;
  }

 private:
  // Uniform in the capsule around a-b: uniform in its bounding cylinder-box, kept when inside.
  [[nodiscard]] Vec3 in_capsule(const Vec3& a, const Vec3& b, scene_files::Rng& rng) const {
    const double length = (b - a).norm();
    const Vec3 axis = length > 0.0 ? Vec3((b - a) / length) : Vec3::UnitZ();
    const Vec3 u = axis.unitOrthogonal();
    const Vec3 v = axis.cross(u);
    for (;;) {
      const Vec3 q = a + rng.uniform(-r_, length + r_) * axis + rng.uniform(-r_, r_) * u + rng.uniform(-r_, r_) * v;
      if (distance_to_segment(q, a, b) <= r_) return q;
    }
  }

  std::span<const Vec3> stops_;
  double r_;
  std::vector<double> cumulative_;
};

// Which points lie within r of the path: each segment is walked in steps of at most r, and each
// step marks the grid cells (side 2r) meeting the box of half-side 1.5 r around it. A point within
// r of a segment is within r / 2 + r of one of its steps, so its cell lists that segment; the
// exact distance decides. A path too long for its radius (over kMaxMarks steps) is tested
// against every segment instead.
class TubeIndex {
 public:
  TubeIndex(std::span<const Vec3> stops, double radius) : stops_(stops), r_(radius), cell_(2.0 * radius) {
    double steps = 0.0;
    for (std::size_t i = 0; i + 1 < stops.size(); ++i) steps += std::ceil((stops[i + 1] - stops[i]).norm() / r_) + 1.0;
    indexed_ = steps <= kMaxMarks;
    if (!indexed_) return;
    for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
      const Vec3& a = stops[i];
      const Vec3& b = stops[i + 1];
      const auto n = static_cast<std::size_t>(std::ceil((b - a).norm() / r_));
      for (std::size_t k = 0; k <= n; ++k) {
        mark(n == 0 ? a : Vec3(a + (b - a) * (static_cast<double>(k) / static_cast<double>(n))),
             static_cast<std::uint32_t>(i));
      }
    }
  }

  [[nodiscard]] bool contains(const Vec3& q) const {
    if (!indexed_) return near_segment(q, 0, stops_.size() - 1);
    const auto it = cells_.find(key(cell(q.x()), cell(q.y()), cell(q.z())));
    if (it == cells_.end()) return false;
    for (const std::uint32_t i : it->second) {
      if (distance_to_segment(q, stops_[i], stops_[i + 1]) <= r_) return true;
    }
    return false;
  }

 private:
  static constexpr double kMaxMarks = 4e6;

  [[nodiscard]] bool near_segment(const Vec3& q, std::size_t from, std::size_t to) const {
    for (std::size_t i = from; i < to; ++i) {
      if (distance_to_segment(q, stops_[i], stops_[i + 1]) <= r_) return true;
    }
    return false;
  }
  [[nodiscard]] std::int64_t cell(double x) const { return static_cast<std::int64_t>(std::floor(x / cell_)); }
  [[nodiscard]] static std::uint64_t key(std::int64_t x, std::int64_t y, std::int64_t z) {
    const auto bits = [](std::int64_t c) { return static_cast<std::uint64_t>(c) & 0x1FFFFFu; };  // 21 bits each
    return bits(x) << 42 | bits(y) << 21 | bits(z);
  }
  // Segments come in order, so a cell's list repeats a segment only at its back.
  void mark(const Vec3& p, std::uint32_t segment) {
    const double h = 1.5 * r_;
    for (std::int64_t x = cell(p.x() - h); x <= cell(p.x() + h); ++x) {
      for (std::int64_t y = cell(p.y() - h); y <= cell(p.y() + h); ++y) {
        for (std::int64_t z = cell(p.z() - h); z <= cell(p.z() + h); ++z) {
          std::vector<std::uint32_t>& list = cells_[key(x, y, z)];
          if (list.empty() || list.back() != segment) list.push_back(segment);
        }
      }
    }
  }

  std::span<const Vec3> stops_;
  double r_;
  double cell_;
  bool indexed_ = false;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

void check_arguments(const InspectionGraph& base, std::span<const Vec3> base_positions, std::span<const Vec3> stops,
                     std::span<const VertexId> stop_vertices, const CorridorOptions& o) {
  if (base_positions.size() < base.vertex_count()) {
    throw std::invalid_argument(
        fmt::format("corridor: {} positions for {} vertices", base_positions.size(), base.vertex_count()));
  }
  if (stops.size() != stop_vertices.size() || stops.empty()) {
    throw std::invalid_argument(
        fmt::format("corridor: {} stops with {} vertex ids", stops.size(), stop_vertices.size()));
  }
  if (stop_vertices.front() != 0 || stop_vertices.back() != 0) {
    throw std::invalid_argument("corridor: the flown path must begin and end at vertex 0, the root");
  }
  for (const VertexId v : stop_vertices) {
    if (v != kNoVertex && v >= base.vertex_count()) {
      throw std::invalid_argument(fmt::format("corridor: stop vertex {} is not in the graph", v));
    }
  }
  if (!(o.radius > 0.0) || !(o.join_radius > 0.0) || !(o.density >= 0.0) || !std::isfinite(o.density)) {
    throw std::invalid_argument(fmt::format("corridor: radius {}, join radius {} and density {} must be positive",
                                            o.radius, o.join_radius, o.density));
  }
}

// Builds the graph as it grows: vertices with their chi, edges, and which vertices are new.
struct Growing {
  std::vector<Vec3> positions;
  std::vector<std::vector<PoiId>> visible;
  std::vector<RoadmapEdge> edges;
  std::vector<VertexId> added;  // vertices that are not the base's: each is joined

  VertexId add(const Scene& scene, const Vec3& q) {
    const auto id = static_cast<VertexId>(positions.size());
    positions.push_back(q);
    visible.push_back(scene.visibility().visible_pois(q));
    added.push_back(id);
    return id;
  }
};

// The stop, or the budget from `start`.
bool should_stop(const CorridorOptions& o, std::chrono::steady_clock::time_point start) {
  return (o.stop != nullptr && o.stop->load()) ||
         (o.budget_seconds > 0.0 &&
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= o.budget_seconds);
}

// Joins each added vertex to its nearest vertices within the join radius (at most max_joins;
// each pair once: from the later vertex), by checked segments.
void join(const Scene& scene, const CorridorOptions& o, std::chrono::steady_clock::time_point start, Growing& g,
          CorridorGraph& out) {
  PointGrid grid(o.join_radius);
  for (std::size_t v = 0; v < g.positions.size(); ++v) grid.insert(static_cast<std::uint32_t>(v), g.positions[v]);
  std::vector<std::pair<double, std::uint32_t>> near;
  for (std::size_t i = 0; i < g.added.size(); ++i) {
    if (i % 16 == 0 && should_stop(o, start)) {
      out.stopped = true;
      return;
    }
    const VertexId u = g.added[i];
    grid.within(g.positions[u], o.join_radius, g.positions, near);
    std::size_t joined = 0;
    for (const auto& [d, w] : near) {  // nearest first
      if (w == u) continue;
      if (o.max_joins > 0 && joined >= o.max_joins) break;
      ++joined;
      if (w > u) continue;  // joined from w, or to be
      ++out.segments_checked;
      if (scene.segment_valid(g.positions[u], g.positions[w])) g.edges.push_back({w, u, d});
    }
  }
}

// Keeps a tube sample that is in the scene's box and valid.
bool keep_sample(const Scene& scene, const Vec3& q, Growing& g, CorridorGraph& out) {
  if (!scene.config().bounds.contains(q) || !scene.point_valid(q)) return false;
  g.add(scene, q);
  ++out.samples;
  return true;
}

// Fresh draws, uniform over the tube at the options' density.
void add_fresh(const Scene& scene, std::span<const Vec3> stops, const CorridorOptions& o,
               std::chrono::steady_clock::time_point start, Growing& g, CorridorGraph& out) {
  const Tube tube(stops, o.radius);
  const double wanted = std::ceil(o.density * tube.capsule_volume());
  const auto draws = static_cast<std::size_t>(std::min(wanted, static_cast<double>(o.max_samples)));
  scene_files::Rng rng(o.seed);
  for (std::size_t k = 0; k < draws; ++k) {
    if (k % 64 == 0 && should_stop(o, start)) {
      out.stopped = true;
      return;
    }
    const std::optional<Vec3> q = tube.draw(rng);
    if (!q) continue;
    ++out.draws;
    keep_sample(scene, *q, g, out);
  }
}

// The given samples, or the build's stream drawn again, that lie in the tube (the first
// max_samples kept); a base vertex's own position is not added again.
void add_found(const Scene& scene, std::span<const Vec3> stops, const CorridorOptions& o,
               std::chrono::steady_clock::time_point start, Growing& g, CorridorGraph& out) {
  const TubeIndex tube(stops, o.radius);
  PointGrid base(o.radius);
  const std::size_t n = g.positions.size();
  for (std::size_t v = 0; v < n; ++v) base.insert(static_cast<std::uint32_t>(v), g.positions[v]);
  std::vector<std::pair<double, std::uint32_t>> same;
  const std::uint64_t count = o.source == CorridorSource::samples ? o.samples.size() : o.stream_count;
  scene_files::Rng stream(o.stream_seed);
  for (std::uint64_t k = 0; k < count && out.samples < o.max_samples; ++k) {
    if (k % 4096 == 0 && should_stop(o, start)) {
      out.stopped = true;
      return;
    }
    const Vec3 q = o.source == CorridorSource::samples ? o.samples[k] : stream.uniform_in(scene.config().bounds);
    if (!tube.contains(q)) continue;
    ++out.draws;
    base.within(q, 0.0, std::span<const Vec3>(g.positions).first(n), same);
    if (same.empty()) keep_sample(scene, q, g, out);
  }
}

}  // namespace

CorridorGraph corridor_graph(const Scene& scene, const InspectionGraph& base, std::span<const Vec3> base_positions,
                             std::span<const Vec3> stops, std::span<const VertexId> stop_vertices,
                             const CorridorOptions& o) {
  check_arguments(base, base_positions, stops, stop_vertices, o);
  const auto start = std::chrono::steady_clock::now();
  CorridorGraph out;
  Growing g;
  const std::size_t n = base.vertex_count();
  g.positions.assign(base_positions.begin(), base_positions.begin() + static_cast<std::ptrdiff_t>(n));
  g.visible.reserve(n);
  for (VertexId v = 0; v < n; ++v) g.visible.emplace_back(base.visible(v).begin(), base.visible(v).end());
  g.edges.assign(base.edges().begin(), base.edges().end());
  // The flown path: its stops (new vertices where they are not the base's) and its segments.
  for (std::size_t i = 0; i < stops.size(); ++i) {
    out.walk.push_back(stop_vertices[i] != kNoVertex ? stop_vertices[i] : g.add(scene, stops[i]));
  }
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
    if (out.walk[i] != out.walk[i + 1])
      g.edges.push_back({out.walk[i], out.walk[i + 1], (stops[i + 1] - stops[i]).norm()});
  }
  if (o.source == CorridorSource::fresh) {
    add_fresh(scene, stops, o, start, g, out);
  } else {
    add_found(scene, stops, o, start, g, out);
  }
  join(scene, o, start, g, out);
  out.positions = g.positions;
  out.graph = InspectionGraph::from_edges(g.positions.size(), g.edges, std::move(g.visible), base.poi_count());
  return out;
}

}  // namespace ispars::planning
