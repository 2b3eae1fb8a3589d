// `ispars-lab build`: one roadmap, its figures, and optionally the roadmap itself.

#include <fmt/format.h>
#include <unistd.h>

#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "experiment_support.hpp"
#include "flags.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/builders/roadmap_builder.hpp"
#include "ispars/planning/builders/roadmap_verifier.hpp"
#include "ispars/planning/builders/spars_builder.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "json_output.hpp"
#include "lab_build.hpp"
#include "timing.hpp"

namespace ispars::lab {
namespace {

nlohmann::json summary(const Roadmap& g) {
  return {{"vertices", g.vertex_count()},
          {"edges", g.edge_count()},
          {"components", g.component_count()},
          {"pois_covered", g.covered_pois()},
          {"pois_covered_root", g.covered_pois_in_component_of(0)},
          {"digest", roadmap_digest(g)}};
}

void write_file(const std::string& path, const std::string& field, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw params::InputError(path, field, "cannot open for writing");
  out << text;
  if (!out) throw params::InputError(path, field, "write failed");
}

void write_iris(const std::string& prefix, const Roadmap& g) {
  std::string vertex;
  std::string edge;
  std::string conf;
  for (VertexId v = 0; v < g.vertex_count(); ++v) {
    vertex += fmt::format("{} 0 0", v);
    for (const PoiId p : g.visibility_table().ids(v)) vertex += fmt::format(" {}", p);
    vertex += '\n';
    const Vec3& q = g.position(v);
    conf += fmt::format("{} {} {} {}\n", v, q.x(), q.y(), q.z());
  }
  for (const RoadmapEdge& e : g.edges()) edge += fmt::format("{} {} 1 1 0 0 {}\n", e.u, e.v, e.cost);
  write_file(prefix + "_vertex", "--iris", vertex);
  write_file(prefix + "_edge", "--iris", edge);
  write_file(prefix + "_conf", "--iris", conf);
}

void progress(std::size_t done, std::size_t total, const Roadmap& g, double seconds) {
  const int width = 30;
  const int filled = total == 0 ? width : static_cast<int>(width * done / total);
  std::cerr << fmt::format("\r[{:<{}}] {:3d}% {}/{} samples, {} vertices, {} edges, {:.1f} s",
                           std::string(static_cast<std::size_t>(filled), '#'), width,
                           total == 0 ? 100 : static_cast<int>(100 * done / total), done, total, g.vertex_count(),
                           g.edge_count(), seconds)
            << std::flush;
}

// The human report of a build: `out`, the JSON --json prints, in lines.
void print_report(const nlohmann::json& out, const std::string& method) {
  const auto line = [](const char* name, const nlohmann::json& s) {
    return fmt::format(
        "{:<9}{:>8} vertices {:>8} edges {:>5} components, POIs covered {} ({} in the root's component)\n", name,
        s["vertices"].get<std::size_t>(), s["edges"].get<std::size_t>(), s["components"].get<std::size_t>(),
        s["pois_covered"].get<std::size_t>(), s["pois_covered_root"].get<std::size_t>());
  };
  std::cout << fmt::format("{} on {}: {} samples (seed {}) in {:.2f} s, {:.0f} samples/s\n", method,
                           out["scene"].get<std::string>(), out["samples"].get<std::size_t>(),
                           out["seed"].get<std::uint64_t>(), out["seconds"].get<double>(),
                           out["samples_per_second"].get<double>());
  std::cout << line("roadmap", out["roadmap"]);
  if (out.contains("dense")) std::cout << line("dense", out["dense"]);
  const nlohmann::json& checks = out["checks"];
  std::cout << fmt::format("checks   {} point, {} segment, {} rays\n", checks["point"].get<std::uint64_t>(),
                           checks["segment"].get<std::uint64_t>(), checks["rays"].get<std::uint64_t>());
  if (out.contains("admissions")) {
    std::cout << "admissions " << out["admissions"].dump() << "\nedges by cause " << out["edges_by_cause"].dump()
              << '\n';
  }
  if (out.contains("fresh_samples"))
    std::cout << "Invariant 1 on fresh samples " << out["fresh_samples"].dump() << '\n';
  if (out.contains("verification")) {
    std::cout << "verification " << out["verification"].dump() << ", invariant violations "
              << (out["invariant_violations"].is_null() ? std::string("n/a (no dense pair)")
                                                        : out["invariant_violations"].dump())
              << '\n';
  }
}

}  // namespace

int run_build(const BuildCommandOptions& options) {
  const planning::Scene base = planning::Scene::load(options.scene);
  const LabBuild lab =
      make_lab_build(base, options.method, options.variant, options.request, options.threads, "ispars-lab build");
  const planning::Scene& scene = *lab.scene;
  const auto& builder = lab.builder;
  const std::size_t samples = options.request.samples;

  const planning::CheckCounts before = scene.counts();
  const double t0 = now_seconds();
  const bool show_progress = !options.json && ::isatty(STDERR_FILENO);
  const std::size_t chunk = std::max<std::size_t>(1, samples / 100);
  for (std::size_t done = 0; done < samples;) {
    const std::size_t n = std::min(chunk, samples - done);
    builder->extend(n);
    done += n;
    if (show_progress) progress(done, samples, builder->roadmap(), now_seconds() - t0);
  }
  if (show_progress) std::cerr << '\n';
  const double seconds = now_seconds() - t0;
  const planning::CheckCounts checks = scene.counts() - before;

  nlohmann::json out = {{"scene", scene.config().name},
                        {"method", options.method},
                        {"samples", samples},
                        {"seed", lab.recipe.seed},
                        {"threads", options.threads},
                        {"seconds", seconds},
                        {"samples_per_second", seconds > 0 ? static_cast<double>(samples) / seconds : 0.0},
                        {"roadmap", summary(builder->roadmap())},
                        {"checks", to_json(checks)}};
  if (const Roadmap* dense = builder->dense()) out["dense"] = summary(*dense);
  if (const auto* spars = dynamic_cast<const planning::SparsBuilder*>(builder.get())) {
    const nlohmann::json causes = to_json(spars->admissions());
    out["variant"] = std::string(to_string(lab.recipe.variant));
    out["stretch_slack"] = lab.recipe.stretch_slack;
    out["stretch_slack_after"] = lab.recipe.stretch_slack_after;
    out["admissions"] = causes["admissions"];
    out["edges_by_cause"] = causes["edges_by_cause"];
  }
  if (options.verify) {
    const planning::VerificationReport report =
        builder->dense() != nullptr
            ? planning::verify_sparse_pair(scene, builder->roadmap(), *builder->dense(), builder->dense_ids())
            : planning::verify_roadmap(scene, builder->roadmap());
    out["verification"] = {{"invalid_vertices", report.invalid_vertices},
                           {"invalid_edges", report.invalid_edges},
                           {"wrong_costs", report.wrong_costs},
                           {"sparse_not_dense", report.sparse_not_dense},
                           {"invariant_vertices", report.invariant_vertices}};
    // Invariant 1 relates a sparse roadmap to its dense pair; Dense and IRIS-C have none.
    out["invariant_violations"] =
        builder->dense() != nullptr ? nlohmann::json(report.invariant_violations) : nlohmann::json();
  }
  if (options.fresh > 0) {
    // Fresh samples, not the build's: what the roadmap misses between the samples it drew.
    const planning::VerificationReport fresh =
        planning::verify_fresh_samples(scene, builder->roadmap(), options.fresh, lab.recipe.seed + 1);
    out["fresh_samples"] = {{"samples", fresh.invariant_samples},
                            {"samples_with_a_violation", fresh.invariant_vertices},
                            {"violations", fresh.invariant_violations}};
  }
  if (!options.out.empty()) {
    write_file(options.out, "--out",
               roadmap_file_json(scene.config().name, scene.config().root, scene.pois(), builder->roadmap(),
                                 builder->dense()));
  }
  if (!options.iris.empty()) write_iris(options.iris, builder->roadmap());

  if (options.json) {
    std::cout << out.dump() << std::endl;
    return 0;
  }
  print_report(out, options.method);
  return 0;
}

CLI::App* add_build_command(CLI::App& parent, BuildCommandOptions& options) {
  auto* cmd = parent.add_subcommand("build", "Build a roadmap: dense, spars, ispars, irisc or ispars2");
  cmd->add_option("scene", options.scene, "Scene YAML file")->required();
  add_request_flags(*cmd, options.method, options.variant, options.request);
  cmd->get_option("--method")->required();
  cmd->add_option("--threads", options.threads, "Threads for per-sample checks (same roadmap for any count)")
      ->check(CLI::Range(1u, 64u));
  cmd->add_flag("--verify", options.verify, "Check validity, costs and the inspection invariant exactly");
  cmd->add_option("--fresh", options.fresh, "Also check Invariant 1 on this many fresh samples (a seed of its own)")
      ->check(CLI::Range(std::size_t{0}, std::size_t{10'000'000}));
  cmd->add_option("--out", options.out, "Write the roadmap (and its dense pair) as JSON");
  cmd->add_option("--iris", options.iris, "Write IRIS text files PREFIX_vertex, PREFIX_edge, PREFIX_conf");
  cmd->add_flag("--json", options.json, "Print one JSON object as the last line of stdout");
  return cmd;
}

}  // namespace ispars::lab
