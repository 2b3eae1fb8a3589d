// `ispars-bench peak`: a build's peak resident memory against the memory the daemon admitted it
// for. For each method: a daemon of its own that compacts its store after every commit (so a fold
// of nearly the whole roadmap runs near the build's end, as large as a fold gets), the scene
// loaded, the peak reset (/proc/PID/clear_refs), one build; then the daemon's peak resident
// memory above what it held with the scene loaded, beside the estimate the daemon logged when it
// admitted the build. Then a restart on the same data directory: the peak of a daemon that
// recovers the stored roadmap at start, above a fresh daemon's with the scene loaded.

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <thread>

#include "bench_common.hpp"

namespace ispars::bench {
namespace {

constexpr double kKiBPerMiB = 1024.0;

// Forgets the process's peak resident memory (VmHWM restarts from VmRSS); Linux 4.0 and later.
void reset_peak(pid_t pid) {
  std::ofstream clear("/proc/" + std::to_string(pid) + "/clear_refs");
  clear << "5";
  if (!clear.flush()) throw std::runtime_error("cannot reset the peak of process " + std::to_string(pid));
}

// The last admission the daemon logged: {held MiB, peak MiB}. (No std::regex: GCC 12 warns inside
// <regex> in the sanitizer build, and warnings are errors.)
std::pair<double, double> admitted_mib(const std::string& log) {
  const std::string about = "admitted: about ", held = " MiB held, ", peak = " MiB at its peak";
  const auto at = log.rfind(about);
  const auto held_at = at == std::string::npos ? at : log.find(held, at);
  const auto peak_at = held_at == std::string::npos ? held_at : log.find(peak, held_at);
  if (peak_at == std::string::npos) throw std::runtime_error("the daemon logged no admission");
  return {std::stod(log.substr(at + about.size(), held_at - at - about.size())),
          std::stod(log.substr(held_at + held.size(), peak_at - held_at - held.size()))};
}

// Waits until the store's background compaction has ended: the data directory's journal.old is
// gone (a fold in progress keeps it), for at most a minute.
void wait_for_fold(const std::filesystem::path& data_dir) {
  const auto deadline = Clock::now() + std::chrono::minutes(1);
  while (Clock::now() < deadline) {
    bool folding = false;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(data_dir)) {
      folding = folding || entry.path().filename() == "journal.old";
    }
    if (!folding) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  throw std::runtime_error("the store's compaction did not end within a minute");
}

nlohmann::json run_one(const std::string& daemon_binary, const std::string& method, std::uint64_t samples) {
  Bench bench(daemon_binary, {"--compact-every", "1"});
  Client client(bench.options());
  client.load("tower");
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const pid_t pid = bench.daemon->pid();
  reset_peak(pid);
  const double loaded = proc_status_kib(pid, "VmRSS:") / kKiBPerMiB;
  client.build("tower", ispars::request_of(method, samples));
  const client::SceneStatus done = client.wait_idle("tower", {}, std::chrono::hours(4));
  if (done.samples_done != samples) throw std::runtime_error(method + " stopped early: " + done.last_error);
  wait_for_fold(bench.dir / "data");
  const double peak = proc_status_kib(pid, "VmHWM:") / kKiBPerMiB;
  const double held = proc_status_kib(pid, "VmRSS:") / kKiBPerMiB;
  const auto [estimate_held, estimate_peak] = admitted_mib(bench.daemon->log());

  bench.restart(daemon_binary);  // recovers the stored roadmap before it announces itself
  wait_for_fold(bench.dir / "data");
  const double recovered_peak = proc_status_kib(bench.daemon->pid(), "VmHWM:") / kKiBPerMiB;
  nlohmann::json row{{"method", method},
                     {"samples", samples},
                     {"vertices", done.vertices},
                     {"edges", done.edges},
                     {"dense_vertices", done.dense_vertices},
                     {"dense_edges", done.dense_edges},
                     {"rss_loaded_mib", loaded},
                     {"rss_built_mib", held},
                     {"build_peak_above_loaded_mib", peak - loaded},
                     {"recovery_peak_above_loaded_mib", recovered_peak - loaded},
                     {"estimate_held_mib", estimate_held},
                     {"estimate_peak_mib", estimate_peak}};
  row["within_estimate"] = peak - loaded <= estimate_peak && recovered_peak - loaded <= estimate_peak;
  std::cerr << row.dump() << std::endl;
  return row;
}

}  // namespace

nlohmann::json run_peak(const std::string& daemon_binary, std::uint64_t samples,
                        const std::vector<std::string>& methods) {
  nlohmann::json rows = nlohmann::json::array();
  bool all_within = true;
  for (const std::string& method : methods) {
    rows.push_back(run_one(daemon_binary, method, samples));
    all_within = all_within && rows.back()["within_estimate"].get<bool>();
  }
  return {{"bench", "peak"}, {"samples", samples}, {"all_within_estimate", all_within}, {"runs", rows}};
}

}  // namespace ispars::bench
