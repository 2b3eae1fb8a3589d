// ispars-bench: service benchmarks that print one JSON object each (last line of stdout).
//
//   rtt       stats-query round trips against isparsd, and a raw Fast DDS ping-pong of the same
//             sizes, measured in the same run, alternating in blocks
//   stream    update streaming throughput to 1 and to 8 subscribers
//   snapshot  transfer of a roadmap of at least --vertices vertices
//   memory    daemon resident memory per 100,000 dense vertices
//   peak      a build's peak resident memory (with its compaction fold, and a recovery)
//             against the estimate the daemon admitted it for (peak_bench.cpp)
//   grow      a roadmap extended step by step to millions of samples, then a restart (grow_bench.cpp)
//
// Every run starts its own isparsd (next to this binary unless --daemon) on a random domain
// with the localhost-only profile, in a temporary directory, and stops it at the end.

#include <fmt/format.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <CLI/CLI.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "bench_common.hpp"
#include "ispars/client/client.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/local/local_daemon.hpp"
#include "ispars/params/cli_archive.hpp"
#include "ispars/roadmap/build_recipe.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace {

using namespace ispars::bench;

nlohmann::json run_stream(const std::string& daemon_binary, std::uint64_t samples, const std::string& method) {
  nlohmann::json rows = nlohmann::json::array();
  for (const int subscribers : {0, 1, 8}) {
    Bench bench(daemon_binary);
    Client control(bench.options());
    control.load("tower");
    std::vector<std::unique_ptr<Client>> clients;
    std::vector<std::unique_ptr<ispars::client::RoadmapReplica>> replicas;
    for (int i = 0; i < subscribers; ++i) {
      clients.push_back(std::make_unique<Client>(bench.options()));
      replicas.push_back(std::make_unique<ispars::client::RoadmapReplica>(*clients.back(), "tower"));
    }
    for (auto& r : replicas) r->wait_for(0, 0, std::chrono::seconds(30));  // first (empty) sync
    const auto t0 = Clock::now();
    control.build("tower", ispars::request_of(method, samples));
    const auto done = control.wait_idle("tower", {}, std::chrono::hours(1));
    const double build_seconds = seconds_since(t0);
    bool all_equal = true;
    for (auto& r : replicas) {
      r->wait_for(done.generation, done.version, std::chrono::seconds(120));
    }
    const double seconds = seconds_since(t0);
    const std::uint64_t digest = ispars::roadmap_digest(control.snapshot("tower").roadmap);
    std::size_t resyncs = 0;
    for (auto& r : replicas) {
      all_equal = all_equal && ispars::roadmap_digest(r->roadmap()) == digest;
      resyncs += r->snapshots_taken() - 1;
    }
    const double vertices = done.vertices;
    rows.push_back({{"subscribers", subscribers},
                    {"vertices", done.vertices},
                    {"edges", done.edges},
                    {"build_seconds", build_seconds},
                    {"seconds_until_all_replicas_current", seconds},
                    {"vertices_per_second_per_subscriber", vertices / seconds},
                    {"vertices_per_second_total", vertices * subscribers / seconds},
                    {"replicas_equal_server", all_equal},
                    {"resyncs", resyncs}});
    std::cerr << rows.back().dump() << "\n";
  }
  return {{"bench", "stream"}, {"method", method}, {"samples", samples}, {"runs", rows}};
}

nlohmann::json run_snapshot(const std::string& daemon_binary, std::uint64_t vertices, int repeats) {
  Bench bench(daemon_binary);
  Client client(bench.options());
  client.load("tower");
  // Dense keeps (nearly) every valid sample: the quickest way to a roadmap of this size.
  client.build("tower", ispars::request_of("dense", vertices + vertices / 20));
  const auto done = client.wait_idle("tower", {}, std::chrono::hours(1));
  std::vector<double> times;
  std::size_t bytes = 0;
  for (int i = 0; i < repeats; ++i) {
    const auto t0 = Clock::now();
    const auto s = client.snapshot("tower");
    times.push_back(seconds_since(t0));
    bytes = ispars::encode_batch(ispars::batch_since(s.roadmap, 0)).size();
  }
  return {{"bench", "snapshot"},
          {"vertices", done.vertices},
          {"edges", done.edges},
          {"bytes", bytes},
          {"median_seconds", percentile(times, 0.5)},
          {"max_seconds", percentile(times, 1.0)},
          {"megabytes_per_second", static_cast<double>(bytes) / 1e6 / percentile(times, 0.5)}};
}

std::size_t rss_kib(pid_t pid) { return proc_status_kib(pid, "VmRSS:"); }

nlohmann::json run_memory(const std::string& daemon_binary, std::uint64_t samples) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string method : {"dense", "ispars"}) {
    Bench bench(daemon_binary);
    Client client(bench.options());
    client.load("tower");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::size_t before = rss_kib(bench.daemon->pid());
    client.build("tower", ispars::request_of(method, samples));
    const auto done = client.wait_idle("tower", {}, std::chrono::hours(1));
    // What the daemon holds, not what its store's background compaction holds for a moment
    // after the build (measured 300 ms after it: ispars 574-703 MiB; 6 s after: 368 MiB).
    std::this_thread::sleep_for(std::chrono::seconds(6));
    const std::size_t after = rss_kib(bench.daemon->pid());
    const double dense = method == "dense" ? done.vertices : done.dense_vertices;
    rows.push_back({{"method", method},
                    {"samples", samples},
                    {"dense_vertices", dense},
                    {"dense_edges", method == "dense" ? done.edges : done.dense_edges},
                    {"sparse_vertices", method == "dense" ? 0u : done.vertices},
                    {"rss_loaded_mib", before / 1024.0},
                    {"rss_built_mib", after / 1024.0},
                    {"mib_per_100k_dense_vertices", (after - before) / 1024.0 / (dense / 1e5)}});
    std::cerr << rows.back().dump() << "\n";
  }
  return {{"bench", "memory"}, {"runs", rows}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ispars-bench: isparsd service benchmarks (JSON on the last stdout line)"};
  app.require_subcommand(1);
  std::string daemon = (std::filesystem::canonical("/proc/self/exe").parent_path() / "isparsd").string();
  app.add_option("--daemon", daemon, "the isparsd binary");
  int count = 2000;
  auto* rtt = app.add_subcommand("rtt", "stats round trip against a raw Fast DDS ping-pong");
  rtt->add_option("--count", count, "round trips per path (multiple of 100)");
  std::string keystore_script;
  rtt->add_option("--security", keystore_script,
                  "also measure under DDS Security, with a keystore this script makes "
                  "(deploy/security/make-keystore.sh)");
  std::uint64_t samples = 20000;
  std::string method = "dense";
  auto* stream = app.add_subcommand("stream", "update streaming to 0, 1 and 8 subscribers");
  stream->add_option("--samples", samples, "samples of the streamed build");
  stream->add_option("--method", method, "method of the streamed build");
  std::uint64_t vertices = 100000;
  int repeats = 3;
  auto* snapshot = app.add_subcommand("snapshot", "snapshot transfer of a large roadmap");
  snapshot->add_option("--vertices", vertices, "roadmap size");
  snapshot->add_option("--repeats", repeats, "transfers");
  std::uint64_t memory_samples = 100000;
  auto* memory = app.add_subcommand("memory", "daemon memory per 100,000 dense vertices");
  memory->add_option("--samples", memory_samples, "samples per build");
  std::uint64_t peak_samples = 100000;
  std::vector<std::string> peak_methods{"dense", "ispars", "irisc", "ispars2"};
  auto* peak = app.add_subcommand("peak", "a build's peak memory (compaction fold, recovery) against its estimate");
  peak->add_option("--samples", peak_samples, "samples per build")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{10'000'000}));
  peak->add_option("--methods", peak_methods, "build methods")
      ->check(CLI::IsMember({"dense", "spars", "ispars", "irisc", "ispars2"}));
  std::string grow_scenes, grow_scene = "water_tower", grow_method = "ispars2";
  std::uint64_t grow_samples = 1'000'000, grow_step = 100'000;
  ispars::BuildRequest grow_build;
  auto* grow = app.add_subcommand("grow", "a roadmap extended step by step: cost per sample, memory, restart");
  grow->add_option("--scene-dir", grow_scenes, "scene directory (deploy/scenes)")
      ->required()
      ->check(CLI::ExistingDirectory);
  grow->add_option("--scene", grow_scene, "scene name");
  grow->add_option("--method", grow_method, "build method");
  grow->add_option("--samples", grow_samples, "samples in all")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  grow->add_option("--step", grow_step, "samples per extend")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{100'000'000}));
  ispars::params::add_flags(*grow, grow_build.overrides);  // the build's overrides
  int echo_domain = 0;
  std::string echo_security, echo_client, echo_reply;
  auto* echo = app.add_subcommand("echo", "")->group("");  // hidden: rtt's raw echo server
  echo->add_option("--domain", echo_domain);
  echo->add_option("--security", echo_security);
  echo->add_option("--client", echo_client);
  echo->add_option("--reply", echo_reply);
  CLI11_PARSE(app, argc, argv);
  try {
    if (*echo) return run_echo(echo_domain, echo_security, echo_client, echo_reply);
    nlohmann::json out;
    if (*rtt) out = run_rtt(daemon, std::max(100, count), keystore_script);
    if (*stream) out = run_stream(daemon, samples, method);
    if (*snapshot) out = run_snapshot(daemon, vertices, repeats);
    if (*memory) out = run_memory(daemon, memory_samples);
    if (*peak) out = run_peak(daemon, peak_samples, peak_methods);
    if (*grow) {
      ispars::set_method(grow_build, grow_method, "", "--method");
      out = run_grow(daemon, grow_scenes, grow_scene, grow_build, grow_samples, grow_step);
    }
    std::cout << out.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ispars-bench: " << e.what() << "\n";
    return 1;
  }
}
