#include "experiment_support.hpp"

#include <cstdlib>
#include <fstream>

#include <cmath>

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "timing.hpp"

namespace ispars::lab {

void run_gnuplot(const std::string& png, const std::string& script) {
  const std::string script_path = png + ".gnuplot";
  {
    std::ofstream file(script_path);
    file << script;
  }
  const std::string command = "gnuplot '" + script_path + "' 2>&1";
  const int status = std::system(command.c_str());
  std::remove(script_path.c_str());
  if (status != 0) {
    throw std::runtime_error("gnuplot failed (is gnuplot-nox installed? deploy/install-deps.sh installs it)");
  }
}

MeanSd mean_sd(const std::vector<double>& values) {
  if (values.empty()) return {};
  double sum = 0.0;
  for (const double v : values) sum += v;
  const double mean = sum / static_cast<double>(values.size());
  double squares = 0.0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  const double sd = values.size() > 1 ? std::sqrt(squares / static_cast<double>(values.size() - 1)) : 0.0;
  return {mean, sd};
}

std::string mean_sd_cell(const std::vector<double>& values, int decimals) {
  if (values.empty()) return "-";
  const MeanSd m = mean_sd(values);
  return fmt::format("{:.{}f} +- {:.{}f}", m.mean, decimals, m.sd, decimals);
}

scene_files::SceneConfig scene_variant(const scene_files::SceneConfig& base, std::size_t pois, std::uint64_t poi_seed,
                                       double delta) {
  scene_files::SceneConfig c = base;
  if (pois > 0) {
    c.pois.count = pois;
    c.pois.seed = poi_seed;
    c.pois.file.clear();
  }
  if (delta > 0.0) {
    c.dense_delta = delta;
    c.sparse_delta = 1.5 * delta;
  }
  return c;
}

double dense_mean_degree(const planning::Scene& scene, std::size_t samples, unsigned threads) {
  planning::BuildOptions options;
  options.seed = 1;
  options.threads = threads;
  const auto builder = planning::make_roadmap_builder(BuildMethod::dense, scene, options);
  builder->extend(samples);
  const Roadmap& g = builder->roadmap();
  return 2.0 * static_cast<double>(g.edge_count()) / static_cast<double>(g.vertex_count());
}

double calibrate_delta(const scene_files::SceneConfig& base, std::size_t samples, double target_degree,
                       unsigned threads) {
  // POIs do not change the dense graph: use one, to keep chi(q) cheap.
  const auto degree_at = [&](double delta) {
    return dense_mean_degree(planning::Scene::build(scene_variant(base, 1, 1, delta)), samples, threads);
  };
  // Bracket by steps of 1.25 from the scene's own delta (cheap: evaluations stay near the
  // answer; a much larger delta makes a very dense, slow graph), then bisect geometrically.
  double lo = base.dense_delta;
  double hi = base.dense_delta;
  if (degree_at(lo) < target_degree) {
    do {
      lo = hi;
      hi *= 1.25;
    } while (degree_at(hi) < target_degree);
  } else {
    do {
      hi = lo;
      lo /= 1.25;
    } while (degree_at(lo) > target_degree);
  }
  for (int i = 0; i < 30; ++i) {
    const double mid = std::sqrt(lo * hi);
    const double degree = degree_at(mid);
    if (std::abs(degree - target_degree) <= 0.005 * target_degree) return mid;
    (degree < target_degree ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

RunFigures figures_of(const planning::RoadmapBuilder& builder, const planning::CheckCounts& checks, double seconds) {
  RunFigures f;
  const Roadmap& g = builder.roadmap();
  f.vertices = g.vertex_count();
  f.edges = g.edge_count();
  f.covered = g.covered_pois();
  f.covered_root = g.covered_pois_in_component_of(0);
  if (const Roadmap* d = builder.dense()) {
    f.dense_vertices = d->vertex_count();
    f.dense_edges = d->edge_count();
    f.dense_covered = d->covered_pois();
    f.dense_covered_root = d->covered_pois_in_component_of(0);
  }
  f.checks = checks;
  f.seconds = seconds;
  return f;
}

nlohmann::json to_json(const planning::SparsAdmissions& a) {
  return {{"admissions",
           {{"guard", a.guard},
            {"bridge", a.bridge},
            {"bridge_edge", a.bridge_edge},
            {"interface_edge", a.interface_edge},
            {"interface_vertex", a.interface_vertex},
            {"inspection", a.inspection},
            {"shortcut_edge", a.shortcut_edge},
            {"shortcut_path", a.shortcut_path},
            {"shortcut_path_vertices", a.shortcut_path_vertices},
            {"witness_edge", a.witness_edge},
            {"witness_vertex", a.witness_vertex}}},
          {"edges_by_cause",
           {{"bridge", a.bridge_edges},
            {"interface", a.interface_edges},
            {"shortcut", a.shortcut_edges},
            {"join", a.join_edges},
            {"witness", a.witness_edges}}}};
}

namespace {

nlohmann::json stats_json(const planning::StretchStats& s) {
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json("inf"); };
  return {{"pairs", s.pairs},
          {"disconnected", s.disconnected},
          {"median", number(s.median)},
          {"p95", number(s.p95)},
          {"p99", number(s.p99)},
          {"max", number(s.max)},
          {"share_over_t", s.share_over_t},
          {"max_excess_Delta", number(s.max_excess)}};
}

nlohmann::json bin_json(const planning::StretchBin& b) {
  return {{"from_Delta", b.from},
          {"to_Delta", std::isfinite(b.to) ? nlohmann::json(b.to) : nlohmann::json("inf")},
          {"vs_dense", stats_json(b.vs_dense)},
          {"vs_segment", stats_json(b.vs_segment)}};
}

std::string stats_text(const planning::StretchStats& s) {
  if (s.pairs == 0) return "no pairs";
  return fmt::format(
      "{} pairs, median {:.3f}, p95 {:.3f}, p99 {:.3f}, max {:.3f}, {:.1f}% > t, "
      "max (d_s - t d) / Delta {:.2f}{}",
      s.pairs, s.median, s.p95, s.p99, s.max, 100.0 * s.share_over_t, s.max_excess,
      s.disconnected ? fmt::format(", {} not joined in G_s", s.disconnected) : std::string());
}

}  // namespace

nlohmann::json to_json(const planning::RouteStretchReport& r) {
  nlohmann::json bins = nlohmann::json::array();
  for (const planning::StretchBin& b : r.bins) bins.push_back(bin_json(b));
  return {{"viewpoints", r.viewpoints},
          {"sources", r.sources},
          {"bins", bins},
          {"within_3_Delta", bin_json(r.within_3_delta)},
          {"beyond_3_Delta", bin_json(r.beyond_3_delta)},
          {"all", bin_json(r.all)}};
}

std::string stretch_lines(const planning::RouteStretchReport& r) {
  std::string out;
  const auto line = [&](const planning::StretchBin& b) {
    const std::string range = std::isfinite(b.to) ? fmt::format("[{:.0f},{:.0f}) Delta", b.from, b.to)
                                                  : fmt::format("[{:.0f},inf) Delta", b.from);
    out += fmt::format("  {:<14} d_s/d_dense: {}\n  {:<14} d_s/|x-x'|:  {}\n", range, stats_text(b.vs_dense), "",
                       stats_text(b.vs_segment));
  };
  for (const planning::StretchBin& b : r.bins) line(b);
  line(r.within_3_delta);
  line(r.beyond_3_delta);
  line(r.all);
  return out;
}

const std::vector<PaperSetting>& paper_settings() {
  // Table II of the paper: N, K and the dense roadmap's mean degree 2|E|/|V|.
  static const std::vector<PaperSetting> settings{{"water_tower", 4000, 100, 2.0 * 14474 / 3933},
                                                  {"truss_bridge", 5000, 500, 2.0 * 27508 / 4955},
                                                  {"caric_city", 7000, 500, 2.0 * 16891 / 6391}};
  return settings;
}

const PaperSetting& paper_setting(const std::string& scene) {
  for (const PaperSetting& s : paper_settings()) {
    if (scene == s.scene) return s;
  }
  throw params::InputError("experiment", "--scene",
                           "the paper's setting is known for water_tower, truss_bridge and caric_city only");
}

}  // namespace ispars::lab
