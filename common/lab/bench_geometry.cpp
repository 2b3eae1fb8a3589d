// `ispars-lab bench geometry`: what each geometric query costs, through the fast path (Embree
// BVH + exact tests), FCL, and the brute-force reference over all triangles.

#include <fmt/format.h>

#include <algorithm>
#include <iostream>
#include <optional>
#include <vector>

#include "commands.hpp"
#include "flags.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/reference/brute_force.hpp"
#include "ispars/reference/fcl_checker.hpp"
#include "json_output.hpp"
#include "timing.hpp"

namespace ispars::lab {
namespace {

struct Segment {
  Vec3 a, b;
};

// Segments of length dense_delta from valid points, in random directions, ending in the box.
std::vector<Segment> make_segments(const planning::Scene& scene, scene_files::Rng& rng,
                                   const std::vector<Vec3>& starts) {
  std::vector<Segment> segments;
  const double length = scene.config().dense_delta;
  for (const Vec3& a : starts) {
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const Vec3 b = a + length * rng.unit_vector();
      if (scene.config().bounds.contains(b)) {
        segments.push_back({a, b});
        break;
      }
    }
  }
  return segments;
}

// Valid configurations within sensor range of a random POI: where chi(q) has real work to do.
std::vector<Vec3> make_near_points(const planning::Scene& scene, scene_files::Rng& rng, std::size_t count) {
  std::vector<Vec3> points;
  const double range = scene.config().sensor_range;
  const auto& pois = scene.pois();
  while (points.size() < count) {
    const Vec3& poi = pois[rng.below(pois.size())];
    const Vec3 q = poi + rng.uniform(0.0, range) * rng.unit_vector();
    if (scene.point_valid(q)) points.push_back(q);
  }
  return points;
}

// Queries per timing of the cheap checks (median over batches).
constexpr std::size_t kBatch = 64;

double ratio(double slow, double fast) { return fast > 0.0 ? slow / fast : 0.0; }

// The queries of one run, drawn in this order from one seed.
struct Queries {
  std::vector<Vec3> box_points;    // uniform in the box
  std::vector<Vec3> valid_points;  // valid configurations
  std::vector<Segment> segments;   // from the valid points
  std::vector<Vec3> near_points;   // valid, within sensor range of a POI
};

Queries draw_queries(const planning::Scene& scene, std::size_t n, std::uint64_t seed) {
  scene_files::Rng rng(seed);
  Queries q;
  q.box_points.resize(n);
  for (auto& p : q.box_points) p = rng.uniform_in(scene.config().bounds);
  q.valid_points.resize(n);
  for (auto& p : q.valid_points) p = scene.sample_valid_configuration(rng);
  q.segments = make_segments(scene, rng, q.valid_points);
  q.near_points = make_near_points(scene, rng, n);
  return q;
}

// Median ns per query of each path, and what the fast path's chi(q) cast.
struct Timings {
  double point = 0, segment = 0, chi = 0, chi_near = 0, clearance = 0;
  double fcl_point = 0, fcl_segment = 0;
  double brute_point = 0, brute_segment = 0, brute_chi = 0, brute_chi_near = 0;
  double rays_per_second = 0, rays_per_chi = 0, rays_per_chi_near = 0;
  planning::CheckCounts fast_counts;
};

// The scene's own checks (Embree BVH + exact tests) on every query.
void time_fast(const planning::Scene& scene, const Queries& q, Timings& t, std::size_t& sink) {
  const std::size_t n = q.box_points.size();
  const planning::CollisionChecker& fast = scene.collision();
  const planning::VisibilityOracle& oracle = scene.visibility();
  std::vector<PoiId> chi;
  const planning::CheckCounts before = scene.counts();
  t.point = median_ns_per_call(n, kBatch, [&](std::size_t i) { sink += fast.point_valid(q.box_points[i]); });
  t.segment = median_ns_per_call(q.segments.size(), kBatch,
                                 [&](std::size_t i) { sink += fast.segment_valid(q.segments[i].a, q.segments[i].b); });
  const auto time_chi = [&](const std::vector<Vec3>& points, double& ns, double& seconds) {
    const planning::CheckCounts at = scene.counts();
    const double t0 = now_seconds();
    ns = median_ns_per_call(n, 1, [&](std::size_t i) {
      oracle.visible_pois(points[i], chi);
      sink += chi.size();
    });
    seconds = now_seconds() - t0;
    return (scene.counts() - at).rays;
  };
  double chi_seconds = 0.0, near_seconds = 0.0;
  const std::uint64_t chi_rays = time_chi(q.valid_points, t.chi, chi_seconds);
  const std::uint64_t near_rays = time_chi(q.near_points, t.chi_near, near_seconds);
  t.clearance = median_ns_per_call(n, kBatch, [&](std::size_t i) {
    sink += static_cast<std::size_t>(fast.distance_to_surface(q.valid_points[i]) > 1.0);
  });
  t.fast_counts = scene.counts() - before;
  t.rays_per_second = static_cast<double>(chi_rays + near_rays) / std::max(1e-12, chi_seconds + near_seconds);
  t.rays_per_chi = static_cast<double>(chi_rays) / static_cast<double>(n);
  t.rays_per_chi_near = static_cast<double>(near_rays) / static_cast<double>(n);
}

// FCL on every query; the brute-force reference on the first m, one call per timing (each is long).
void time_references(const reference::FclCollisionChecker& fcl, const reference::BruteForceGeometry& brute,
                     const Queries& q, std::size_t m, Timings& t, std::size_t& sink) {
  const std::size_t n = q.box_points.size();
  t.fcl_point = median_ns_per_call(n, kBatch, [&](std::size_t i) { sink += fcl.point_valid(q.box_points[i]); });
  t.fcl_segment = median_ns_per_call(
      q.segments.size(), kBatch, [&](std::size_t i) { sink += fcl.segment_valid(q.segments[i].a, q.segments[i].b); });
  const std::size_t ms = std::min(m, q.segments.size());
  t.brute_point = median_ns_per_call(m, 1, [&](std::size_t i) { sink += brute.point_valid(q.box_points[i]); });
  t.brute_segment =
      median_ns_per_call(ms, 1, [&](std::size_t i) { sink += brute.segment_valid(q.segments[i].a, q.segments[i].b); });
  t.brute_chi = median_ns_per_call(m, 1, [&](std::size_t i) { sink += brute.visible_pois(q.valid_points[i]).size(); });
  t.brute_chi_near =
      median_ns_per_call(m, 1, [&](std::size_t i) { sink += brute.visible_pois(q.near_points[i]).size(); });
}

// Answers that differ from the reference's on its m queries (chi: outside its tolerance band).
struct Disagreements {
  std::size_t point = 0, segment = 0, fcl_point = 0, fcl_segment = 0, chi = 0, chi_ambiguous = 0;
};

Disagreements count_disagreements(const planning::Scene& scene, const reference::FclCollisionChecker& fcl,
                                  const reference::BruteForceGeometry& brute, const Queries& q, std::size_t m) {
  const planning::CollisionChecker& fast = scene.collision();
  Disagreements d;
  std::vector<PoiId> chi;
  for (std::size_t i = 0; i < m; ++i) {
    const bool reference = brute.point_valid(q.box_points[i]);
    d.point += fast.point_valid(q.box_points[i]) != reference;
    d.fcl_point += fcl.point_valid(q.box_points[i]) != reference;
    for (const Vec3* p : std::initializer_list<const Vec3*>{&q.valid_points[i], &q.near_points[i]}) {
      std::vector<PoiId> ambiguous;
      const std::vector<PoiId> expected = brute.visible_pois(*p, &ambiguous);
      d.chi_ambiguous += ambiguous.size();
      scene.visibility().visible_pois(*p, chi);
      std::vector<PoiId> differ;
      std::set_symmetric_difference(chi.begin(), chi.end(), expected.begin(), expected.end(),
                                    std::back_inserter(differ));
      for (const PoiId id : differ) d.chi += !std::binary_search(ambiguous.begin(), ambiguous.end(), id);
    }
  }
  for (std::size_t i = 0; i < std::min(m, q.segments.size()); ++i) {
    const bool reference = brute.segment_valid(q.segments[i].a, q.segments[i].b);
    d.segment += fast.segment_valid(q.segments[i].a, q.segments[i].b) != reference;
    d.fcl_segment += fcl.segment_valid(q.segments[i].a, q.segments[i].b) != reference;
  }
  return d;
}

// One query's times by path (FCL checks collisions only: no time for chi).
nlohmann::json path_json(double fast, std::optional<double> fcl, double brute) {
  nlohmann::json j = {{"fast", fast}, {"brute_force", brute}, {"speedup_vs_brute_force", ratio(brute, fast)}};
  if (fcl) {
    j["fcl"] = *fcl;
    j["speedup_vs_fcl"] = ratio(*fcl, fast);
  }
  return j;
}

nlohmann::json bench_json(const planning::Scene& scene, const BenchGeometryOptions& options, std::size_t m,
                          const Timings& t, const Disagreements& d) {
  return {
      {"scene", scene.config().name},
      {"triangles", scene.mesh().triangle_count()},
      {"pois", scene.pois().size()},
      {"queries", options.queries},
      {"reference_queries", m},
      {"seed", options.seed},
      {"segment_length", scene.config().dense_delta},
      {"point_check_ns", path_json(t.point, t.fcl_point, t.brute_point)},
      {"segment_check_ns", path_json(t.segment, t.fcl_segment, t.brute_segment)},
      {"chi_ns", path_json(t.chi, std::nullopt, t.brute_chi)},
      {"chi_near_structure_ns", path_json(t.chi_near, std::nullopt, t.brute_chi_near)},
      {"clearance_ns", t.clearance},
      {"rays_per_second", t.rays_per_second},
      {"rays_per_chi", t.rays_per_chi},
      {"rays_per_chi_near_structure", t.rays_per_chi_near},
      {"disagreements",
       {{"point", d.point},
        {"segment", d.segment},
        {"fcl_point", d.fcl_point},
        {"fcl_segment", d.fcl_segment},
        {"chi_pois", d.chi},
        {"chi_pois_in_tolerance_band", d.chi_ambiguous}}},
      {"checks", to_json(t.fast_counts)},
  };
}

void print_bench(const planning::Scene& scene, std::size_t n, std::size_t m, const Timings& t, const Disagreements& d) {
  std::cout << fmt::format(
      "scene {}: {} triangles, {} POIs; {} queries ({} through the brute-force reference)\n"
      "{:<26}{:>12}{:>12}{:>14}{:>12}\n"
      "{:<26}{:>12.0f}{:>12.0f}{:>14.0f}{:>11.0f}x\n"
      "{:<26}{:>12.0f}{:>12.0f}{:>14.0f}{:>11.0f}x\n"
      "{:<26}{:>12.0f}{:>12}{:>14.0f}{:>11.0f}x\n"
      "{:<26}{:>12.0f}{:>12}{:>14.0f}{:>11.0f}x\n"
      "exact clearance: {:.0f} ns; rays: {:.2f} M/s; rays per chi(q): {:.1f} (box), {:.1f} (near)\n"
      "disagreements with the reference: point {}, segment {}, chi {} (+{} POIs in the tolerance band); "
      "FCL: point {}, segment {}\n",
      scene.config().name, scene.mesh().triangle_count(), scene.pois().size(), n, m, "median ns per query", "fast",
      "fcl", "brute force", "speed-up", "point check", t.point, t.fcl_point, t.brute_point,
      ratio(t.brute_point, t.point), fmt::format("segment check (len {:g})", scene.config().dense_delta), t.segment,
      t.fcl_segment, t.brute_segment, ratio(t.brute_segment, t.segment), "chi(q), box samples", t.chi, "-", t.brute_chi,
      ratio(t.brute_chi, t.chi), "chi(q), near structure", t.chi_near, "-", t.brute_chi_near,
      ratio(t.brute_chi_near, t.chi_near), t.clearance, t.rays_per_second / 1e6, t.rays_per_chi, t.rays_per_chi_near,
      d.point, d.segment, d.chi, d.chi_ambiguous, d.fcl_point, d.fcl_segment);
}

}  // namespace

int run_bench_geometry(const BenchGeometryOptions& options) {
  const planning::Scene scene = planning::Scene::load(options.scene);
  const scene_files::SceneConfig& config = scene.config();
  const std::size_t m = std::min(options.reference_queries, options.queries);
  const Queries queries = draw_queries(scene, options.queries, options.seed);
  const reference::FclCollisionChecker fcl(scene.mesh(), config.bounds, config.robot_radius);
  const reference::BruteForceGeometry brute(scene.embree().triangles(), config.bounds, config.robot_radius,
                                            scene.pois(), config.sensor_range);
  std::size_t sink = 0;
  Timings timings;
  time_fast(scene, queries, timings, sink);
  time_references(fcl, brute, queries, m, timings, sink);
  const Disagreements disagreements = count_disagreements(scene, fcl, brute, queries, m);
  if (sink == 0xFFFFFFFF) std::cerr << "";  // keeps the measured calls observable
  if (options.json) {
    std::cout << bench_json(scene, options, m, timings, disagreements).dump() << std::endl;
    return 0;
  }
  print_bench(scene, options.queries, m, timings, disagreements);
  return 0;
}

CLI::App* add_bench_geometry_command(CLI::App& parent, BenchGeometryOptions& options) {
  auto* cmd = parent.add_subcommand("geometry",
                                    "Point, segment and visibility query costs against brute-force and FCL references");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  cmd->add_option("--queries", options.queries, "Queries per fast-path measurement")
      ->check(CLI::Range(std::size_t{64}, std::size_t{10'000'000}));
  cmd->add_option("--reference-queries", options.reference_queries, "Queries through the brute-force reference")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1'000'000}));
  cmd->add_option("--seed", options.seed, "Seed of the random queries");
  return cmd;
}

}  // namespace ispars::lab
