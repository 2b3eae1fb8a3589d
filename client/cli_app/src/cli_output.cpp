#include "ispars/cli_app/cli_output.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <fstream>
#include <iostream>

namespace ispars::cli_app {

nlohmann::json status_json(const client::SceneStatus& s) {
  return {{"scene", s.scene},
          {"server_id", s.server_id},
          {"state", client::to_string(s.state)},
          {"method", s.method},
          {"variant", s.variant},
          {"seed", s.seed},
          {"generation", s.generation},
          {"samples_done", s.samples_done},
          {"samples_target", s.samples_target},
          {"accepted_generation", s.accepted_generation},
          {"version", s.version},
          {"vertices", s.vertices},
          {"edges", s.edges},
          {"components", s.components},
          {"dense_vertices", s.dense_vertices},
          {"dense_edges", s.dense_edges},
          {"poi_count", s.poi_count},
          {"tasks", s.tasks},
          {"pois_covered", s.pois_covered},
          {"pois_covered_root", s.pois_covered_root},
          {"dense_delta", s.dense_delta},
          {"sparse_delta", s.sparse_delta},
          {"stretch", s.stretch},
          {"stretch_slack", s.stretch_slack},
          {"stretch_slack_after", s.stretch_slack_after},
          {"last_error", s.last_error}};
}

void print_status(const client::SceneStatus& s) {
  std::cout << fmt::format("{} on {}: {}", s.scene, s.server_id, client::to_string(s.state));
  if (!s.method.empty()) {
    std::cout << fmt::format(", {}{} seed {}, {}/{} samples\n", s.method,
                             s.variant.empty() ? std::string() : fmt::format(" ({} rules)", s.variant), s.seed,
                             s.samples_done, s.samples_target);
    if (s.stretch_slack > 0.0) {
      std::cout << fmt::format("  stretch: t = {}, slack {} Delta from sample {}\n", s.stretch, s.stretch_slack,
                               s.stretch_slack_after);
    }
    std::cout << fmt::format("  roadmap: {} vertices, {} edges, {} components, version {}\n", s.vertices, s.edges,
                             s.components, s.version);
    if (s.dense_vertices > 0) {
      std::cout << fmt::format("  dense:   {} vertices, {} edges\n", s.dense_vertices, s.dense_edges);
    }
    std::cout << fmt::format(
        "  POIs:    {} of {} seen, {} from the root's component{}\n", s.pois_covered, s.poi_count, s.pois_covered_root,
        s.tasks == 0 ? std::string()
                     : fmt::format(" (with {} task{}: ispars task list)", s.tasks, s.tasks == 1 ? "" : "s"));
  } else {
    std::cout << ", no roadmap\n";
  }
  if (!s.last_error.empty()) std::cout << "  note: " << s.last_error << "\n";
}

// One line of live progress: redrawn in place on a terminal, one line per second otherwise.
Progress::Progress(bool enabled) : enabled_(enabled), tty_(::isatty(STDERR_FILENO) != 0) {}

void Progress::operator()(const client::SceneStatus& s) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const bool busy = client::busy(s.state);
  if (!tty_ && busy && now - last_ < std::chrono::seconds(1)) return;
  last_ = now;
  const double fraction =
      s.samples_target ? static_cast<double>(s.samples_done) / s.samples_target : (busy ? 0.0 : 1.0);
  const int width = 30;
  const int filled = static_cast<int>(width * std::min(1.0, fraction));
  const std::string line = fmt::format(
      "[{:<{}}] {:3.0f}% {} {}/{} samples, {} vertices, {} edges", std::string(static_cast<std::size_t>(filled), '#'),
      width, 100 * fraction, client::to_string(s.state), s.samples_done, s.samples_target, s.vertices, s.edges);
  std::cerr << (tty_ ? "\r" + line : line + "\n") << std::flush;
  drawn_ = true;
}

void Progress::finish() {
  if (enabled_ && tty_ && drawn_) std::cerr << "\n";
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  if (!out) throw CLI::ValidationError("--out", "cannot open " + path + " for writing");
  out << text;
  if (!out) throw CLI::ValidationError("--out", "write to " + path + " failed");
}

int follow_job(client::Client& client, const std::string& scene, const client::Reply& reply, bool wait, bool json) {
  if (!json) std::cout << reply.message << "\n";
  client::SceneStatus final_status = reply.status;
  if (wait) {
    Progress progress(!json);
    final_status = client.wait_idle(
        scene, [&](const client::SceneStatus& s) { progress(s); }, std::chrono::hours(24 * 365));
    progress.finish();
  }
  if (json) {
    std::cout << status_json(final_status).dump() << std::endl;
  } else if (wait) {
    print_status(final_status);
  }
  return wait && final_status.state == client::SceneState::failed ? 1 : 0;
}

}  // namespace ispars::cli_app
