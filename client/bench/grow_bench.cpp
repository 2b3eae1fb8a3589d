// `ispars-bench grow`: a roadmap as a long-running daemon grows it. One build of `step` samples,
// then extends of `step` to `samples` in all; after each, the seconds it took and microseconds
// per sample, the daemon's resident memory, the roadmap's vertices, edges and coverage. Then a
// restart (SIGTERM, start on the same data directory): seconds until the daemon answers with the
// roadmap, and until an extend of 1,000 samples is done (a replay for the dense-pair methods
// and IRIS-C, none for dense and ispars2).

#include <fmt/format.h>

#include <iostream>

#include "bench_common.hpp"
#include "ispars/params/json_archive.hpp"

namespace ispars::bench {
namespace {

nlohmann::json overrides_json(const RecipeOverrides& overrides) {
  nlohmann::json out = nlohmann::json::object();
  params::write_json(overrides, out);
  return out;
}

}  // namespace

nlohmann::json run_grow(const std::string& daemon_binary, const std::filesystem::path& scene_dir,
                        const std::string& scene, BuildRequest build, std::uint64_t samples, std::uint64_t step) {
  Bench bench(daemon_binary, {}, "", "", std::filesystem::absolute(scene_dir));
  Client client(bench.options());
  client.load(scene);
  nlohmann::json rows = nlohmann::json::array();
  std::uint64_t done = 0;
  const auto started = Clock::now();
  while (done < samples) {
    const std::uint64_t n = std::min(step, samples - done);
    const auto t0 = Clock::now();
    if (done == 0) {
      build.samples = n;
      client.build(scene, build);
    } else {
      client.extend(scene, n);
    }
    const client::SceneStatus s = client.wait_idle(scene, {}, std::chrono::hours(24));
    if (s.samples_done != done + n)
      throw std::runtime_error("the build stopped at " + std::to_string(s.samples_done) + ": " + s.last_error);
    const double seconds = seconds_since(t0);
    done += n;
    rows.push_back({{"samples", done},
                    {"seconds", seconds},
                    {"us_per_sample", 1e6 * seconds / static_cast<double>(n)},
                    {"rss_mib", proc_status_kib(bench.daemon->pid(), "VmRSS:") / 1024.0},
                    {"vertices", s.vertices},
                    {"edges", s.edges},
                    {"dense_vertices", s.dense_vertices},
                    {"dense_edges", s.dense_edges},
                    {"pois_covered", s.pois_covered},
                    {"poi_count", s.poi_count}});
    std::cerr << rows.back().dump() << std::endl;
  }
  const double total = seconds_since(started);
  const double peak = proc_status_kib(bench.daemon->pid(), "VmHWM:") / 1024.0;

  const auto t0 = Clock::now();
  bench.restart(daemon_binary);  // returns once it announces itself
  const double announced = seconds_since(t0);
  Client after(bench.options());
  after.load(scene);  // stored roadmaps are loaded at start: this only confirms it
  const client::SceneStatus back = after.stats(scene);
  const double answered = seconds_since(t0);
  if (back.samples_done != samples)
    throw std::runtime_error("the restarted daemon holds " + std::to_string(back.samples_done) + " samples");
  after.extend(scene, 1000);
  const client::SceneStatus extended = after.wait_idle(scene, {}, std::chrono::hours(24));
  const double extended_at = seconds_since(t0);
  if (extended.samples_done != samples + 1000)
    throw std::runtime_error("the extend after the restart failed: " + extended.last_error);
  return {{"bench", "grow"},
          {"scene", scene},
          {"method", std::string(to_string(build.method))},
          {"overrides", overrides_json(build.overrides)},
          {"samples", samples},
          {"step", step},
          {"seconds", total},
          {"peak_rss_mib", peak},
          {"steps", rows},
          {"restart",
           {{"seconds_to_announce", announced},
            {"seconds_to_answer_with_the_roadmap", answered},
            {"seconds_to_extend_1000_more", extended_at},
            {"rss_mib_after_extend", proc_status_kib(bench.daemon->pid(), "VmRSS:") / 1024.0}}}};
}

}  // namespace ispars::bench
