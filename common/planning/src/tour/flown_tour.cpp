#include "ispars/planning/tour/flown_tour.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <utility>

#include "ispars/planning/tour/tour_corridor.hpp"
#include "ispars/planning/tour/tour_shortcut.hpp"

namespace ispars::planning {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kSearchShare = 0.5;         // of a timed budget: the roadmap search; rounds share the rest
constexpr double kCorridorOfRound = 0.8;     // of a timed round: its corridor (refinement ends sooner)
constexpr double kRoundPays = 1e-3;          // a corridor round that gains less ends them
constexpr double kCorridorBuildShare = 0.5;  // of a timed round: drawing and joining (then the search)

// One run of the pipeline: the incumbent flown path (positions, and each stop's vertex in the
// graph it was last searched on) and the stages so far.
class FlownRun {
 public:
  FlownRun(const Scene& scene, const InspectionGraph& graph, std::span<const Vec3> positions, const FlownTourOptions& o)
      : scene_(scene), graph_(graph), positions_(positions), o_(o), valid_([&scene](const Vec3& a, const Vec3& b) {
          return scene.segment_valid(a, b);
        }) {}

  FlownTour run() {
    search_roadmap();
    // Rounds of a corridor around the incumbent, then refinement, while a round pays.
    const std::size_t rounds = std::max<std::size_t>(1, o_.rounds);
    for (std::size_t round = 0; round < rounds && out_.stops.size() > 2 && !stopping(); ++round) {
      const double before = out_.cost;
      const double share = 1.0 / static_cast<double>(rounds - round);  // of what is left
      if (has_corridor() && o_.rounds > 0 && corridor_round(round, share)) stage("corridor");
      if (o_.refine) refine(share);
      if (before - out_.cost < kRoundPays * before) break;
    }
    out_.check = check_flown_tour(scene_, positions_[0], out_.search.targets, out_.stops, out_.cost);
    return std::move(out_);
  }

 private:
  [[nodiscard]] double elapsed() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }
  [[nodiscard]] bool timed() const { return o_.search.max_iterations == 0; }
  [[nodiscard]] bool stopping() const {
    return (o_.search.stop != nullptr && o_.search.stop->load()) ||
           (o_.search.budget_seconds > 0.0 && elapsed() >= o_.search.budget_seconds);
  }
  // Seconds a stage may take: `fraction` of what is left of a timed budget, or all that is left
  // of the cap (equal work: the iterations end the searches).
  [[nodiscard]] double allowance(double fraction) const {
    const double left = std::max(0.0, o_.search.budget_seconds - elapsed());
    return timed() ? fraction * left : left;
  }
  void stage(const char* name) { out_.stages.push_back({name, out_.cost, elapsed()}); }

  // Stage 1: the roadmap search, then its shortcut.
  void search_roadmap() {
    GipOptions s = o_.search;
    s.budget_seconds = timed() ? kSearchShare * o_.search.budget_seconds : o_.search.budget_seconds;
    out_.search = solve_gip(graph_, s);
    out_.walk_cost = out_.search.tour.cost;
    out_.cost = out_.walk_cost;
    out_.graph_vertices = graph_.vertex_count();
    out_.graph_edges = graph_.edge_count();
    stage("walk");
    ShortcutOptions so;
    so.stop = o_.search.stop;
    so.budget_seconds = std::max(0.25, allowance(1.0));
    out_.roadmap_shortcut = shortcut_tour(graph_, positions_, out_.search.targets, out_.search.tour, valid_, so);
    const ShortcutTour& sc = out_.roadmap_shortcut;
    out_.segments_checked += sc.segments_checked;
    out_.stops = sc.path;
    vertices_ = sc.stops;
    out_.cost = sc.cost;
    out_.stopped = sc.stopped;
    stage("shortcut");
  }

  [[nodiscard]] double corridor_density() const {
    if (o_.corridor_density > 0.0) return o_.corridor_density;
    const Vec3 extent = scene_.config().bounds.extent();
    const double volume = extent.x() * extent.y() * extent.z();
    return volume > 0.0 ? o_.density_factor * static_cast<double>(o_.build_samples) / volume : 0.0;
  }

  [[nodiscard]] bool has_corridor() const {
    switch (o_.corridor_source) {
      case CorridorSource::fresh:
        return corridor_density() > 0.0;
      case CorridorSource::samples:
        return !o_.corridor_samples.empty();
      case CorridorSource::stream:
        return o_.build_samples > 0;
    }
    return false;
  }

  [[nodiscard]] CorridorOptions corridor_options(std::size_t round) const {
    const double delta = scene_.config().sparse_delta;
    CorridorOptions co;
    co.radius = o_.corridor_radius > 0.0 ? o_.corridor_radius : delta / 2.0;
    co.join_radius = o_.join_radius > 0.0 ? o_.join_radius : 2.0 * delta;
    co.source = o_.corridor_source;
    co.density = corridor_density();
    co.samples = o_.corridor_samples;
    co.stream_seed = o_.build_seed;
    co.stream_count = o_.build_samples;
    co.max_samples = o_.corridor_max_samples;
    co.max_joins = o_.corridor_max_joins;
    co.seed = o_.search.seed * 0x9E3779B97F4A7C15ull + round + 1;
    co.stop = o_.search.stop;
    return co;
  }

  // Stage 2, one round: a corridor around the incumbent, searched from it; true when it ran to
  // the end (its search may still have found nothing shorter). `share`: of the time left.
  bool corridor_round(std::size_t round, double share) {
    const CorridorOptions co = corridor_options(round);
    const double until = elapsed() + allowance(share * kCorridorOfRound);
    std::vector<VertexId> in_base;  // the stops' vertices in the roadmap's graph, where they are its
    for (const VertexId v : vertices_) in_base.push_back(v < graph_.vertex_count() ? v : kNoVertex);
    in_base.front() = in_base.back() = 0;
    CorridorOptions drawn = co;
    drawn.budget_seconds = timed() ? kCorridorBuildShare * (until - elapsed()) : allowance(1.0);
    const CorridorGraph cg = corridor_graph(scene_, graph_, positions_, out_.stops, in_base, drawn);
    out_.segments_checked += cg.segments_checked;
    if (stopping()) {  // a corridor cut short by its own budget is still searched: it is sound
      out_.stopped = true;
      return false;
    }
    GipOptions s = o_.search;
    s.targets = out_.search.targets;
    s.initial_walk = cg.walk;
    s.lp_bound = false;
    s.on_bound = nullptr;
    s.on_improvement = nullptr;
    s.seed = o_.search.seed + round + 1;
    s.budget_seconds = timed() ? until - elapsed() : allowance(1.0);
    if (!timed()) s.max_iterations = std::min(o_.search.max_iterations, o_.corridor_iterations);
    if (s.budget_seconds <= 0.0) return false;
    const GipResult r = solve_gip(cg.graph, s);
    ShortcutOptions so;
    so.stop = o_.search.stop;
    so.budget_seconds = std::max(0.25, allowance(1.0));
    const ShortcutTour sc = shortcut_tour(cg.graph, cg.positions, out_.search.targets, r.tour, valid_, so);
    out_.segments_checked += sc.segments_checked;
    if (sc.cost < out_.cost) {
      out_.stops = sc.path;
      vertices_ = sc.stops;
      for (VertexId& v : vertices_) {
        if (v >= graph_.vertex_count()) v = kNoVertex;  // a corridor vertex: not the roadmap's
      }
      out_.cost = sc.cost;
      out_.graph_vertices = cg.graph.vertex_count();
      out_.graph_edges = cg.graph.edge_count();
      out_.corridor_samples += cg.samples;
    }
    return true;
  }

  // Stage 3: the stops moved where they shorten the tour, and 2-opt. `share`: of the time left.
  void refine(double share) {
    if (stopping()) return;
    RefineOptions ro = o_.refine_options;
    ro.seed = o_.search.seed + out_.stages.size();
    ro.stop = o_.search.stop;
    ro.budget_seconds = std::max(1e-3, allowance(share));
    out_.refined = refine_viewpoints(scene_, out_.search.targets, out_.stops, ro);
    out_.segments_checked += out_.refined.segments_checked;
    out_.stopped = out_.stopped || out_.refined.stopped;
    out_.cost = path_length(out_.stops);
    vertices_.assign(out_.stops.size(), kNoVertex);  // refined stops are the roadmap's no more
    vertices_.front() = vertices_.back() = 0;        // but the root, which never moves
    stage("refine");
  }

  const Scene& scene_;
  const InspectionGraph& graph_;
  std::span<const Vec3> positions_;
  const FlownTourOptions& o_;
  const SegmentValid valid_;
  const Clock::time_point t0_ = Clock::now();
  FlownTour out_;
  std::vector<VertexId> vertices_;  // each incumbent stop's vertex in the graph it was searched on
};

}  // namespace

FlownTour fly_tour(const Scene& scene, const InspectionGraph& graph, std::span<const Vec3> positions,
                   const FlownTourOptions& options) {
  if (positions.size() < graph.vertex_count() || graph.vertex_count() == 0) {
    throw std::invalid_argument(
        fmt::format("fly_tour: {} positions for {} vertices", positions.size(), graph.vertex_count()));
  }
  if (options.search.root != 0) throw std::invalid_argument("fly_tour: the root must be vertex 0");
  if ((positions[0] - scene.config().root).norm() > 1e-6) {
    throw std::invalid_argument("fly_tour: vertex 0 is not the scene's root: not the roadmap's scene");
  }
  if (graph.poi_count() > scene.pois().size()) {  // a task's POIs, say, that the scene does not hold
    throw std::invalid_argument(fmt::format("fly_tour: the graph has {} POIs, its scene {}: not the roadmap's scene",
                                            graph.poi_count(), scene.pois().size()));
  }
  FlownRun run(scene, graph, positions, options);
  return run.run();
}

}  // namespace ispars::planning
