// ispars-bench: service benchmarks that print one JSON object each (last line of stdout).
//
//   rtt       stats-query round trips against isparsd, and a raw Fast DDS ping-pong of the same
//             sizes, measured in the same run, alternating in blocks
//   stream    update streaming throughput to 1 and to 8 subscribers
//   snapshot  transfer of a roadmap of at least --vertices vertices
//   memory    daemon resident memory per 100,000 dense vertices
//
// Every run starts its own isparsd (next to this binary unless --daemon) on a random domain
// with the localhost-only profile, in a temporary directory, and stops it at the end.

#include <CLI/CLI.hpp>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <iostream>
#include <mutex>
#include <thread>

#include "ispars/client/client.hpp"
#include "support/local_daemon.hpp"
#include "ispars/client/replica.hpp"
#include "ispars/roadmap/roadmap_log.hpp"
#include "ispars/wire/topics.hpp"
#include "isparsPubSubTypes.h"

namespace {

namespace fdds = eprosima::fastdds::dds;
using Clock = std::chrono::steady_clock;
using ispars::client::Client;
using ispars::client::LocalDaemon;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

// A temporary working directory with the scenes, a data directory and a running daemon.
struct Bench {
  Bench(const std::string& daemon_binary, std::vector<std::string> extra = {}) {
    char pattern[] = "/tmp/ispars-bench-XXXXXX";
    dir = ::mkdtemp(pattern);
    ispars::client::write_tank_tower_scenes(dir / "scenes", {"tower", "tower2"});
    domain = ispars::client::random_domain();
    daemon = std::make_unique<LocalDaemon>(daemon_binary, domain, dir / "data", dir / "scenes", "bench", std::move(extra));
  }
  ~Bench() {
    daemon.reset();
    std::filesystem::remove_all(dir);
  }
  ispars::client::ClientOptions options() const {
    auto o = ispars::client::local_client_options(domain);
    o.timeout = std::chrono::seconds(120);
    return o;
  }
  std::filesystem::path dir;
  int domain = 0;
  std::unique_ptr<LocalDaemon> daemon;
};

// ---- raw ping-pong: the same QueryRequest/Reply types and QoS, no service logic ------------

struct RawEndpoints final : public fdds::DataReaderListener {
  RawEndpoints(int domain, const char* in_topic_name, const char* out_topic_name, bool is_server)
      : participant({domain, "", "ispars", "raw ping-pong"}), server(is_server) {
    fdds::DomainParticipant* p = participant.get();
    auto* ping = ispars::wire::find_or_create_topic(p, request_type, "bench/ping");
    auto* pong = ispars::wire::find_or_create_topic(p, reply_type, "bench/pong");
    (void)in_topic_name;
    (void)out_topic_name;
    auto* pub = p->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    auto* sub = p->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    writer = pub->create_datawriter(server ? pong : ping, ispars::wire::request_reply_writer_qos());
    reader = sub->create_datareader(server ? ping : pong, ispars::wire::request_reply_reader_qos(), this,
                                    fdds::StatusMask::data_available());
  }
  ~RawEndpoints() override { reader->set_listener(nullptr); }

  void on_data_available(fdds::DataReader* r) override {
    fdds::SampleInfo info;
    if (server) {
      ispars::msg::QueryRequest request;
      while (r->take_next_sample(&request, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        ispars::msg::Reply reply = reply_template;
        reply.client_id(request.client_id());
        reply.request_seq(request.request_seq());
        writer->write(&reply);
      }
    } else {
      ispars::msg::Reply reply;
      while (r->take_next_sample(&reply, &info) == ReturnCode_t::RETCODE_OK) {
        if (!info.valid_data) continue;
        std::lock_guard lock(mutex);
        last_seq = reply.request_seq();
        arrived.notify_all();
      }
    }
  }

  bool matched() {
    fdds::PublicationMatchedStatus pub;
    fdds::SubscriptionMatchedStatus sub;
    writer->get_publication_matched_status(pub);
    reader->get_subscription_matched_status(sub);
    return pub.current_count > 0 && sub.current_count > 0;
  }

  double round_trip(ispars::msg::QueryRequest& request) {
    const auto t0 = Clock::now();
    writer->write(&request);
    std::unique_lock lock(mutex);
    arrived.wait_for(lock, std::chrono::seconds(5), [&] { return last_seq == request.request_seq(); });
    return seconds_since(t0);
  }

  ispars::wire::Participant participant;
  bool server;
  fdds::TypeSupport request_type{new ispars::msg::QueryRequestPubSubType()};
  fdds::TypeSupport reply_type{new ispars::msg::ReplyPubSubType()};
  fdds::DataWriter* writer = nullptr;
  fdds::DataReader* reader = nullptr;
  ispars::msg::Reply reply_template;
  std::mutex mutex;
  std::condition_variable arrived;
  std::uint64_t last_seq = 0;
};

nlohmann::json run_rtt(const std::string& daemon_binary, int count) {
  Bench bench(daemon_binary);
  Client client(bench.options());
  client.load("tower");
  client.build("tower", {"ispars", 2000, 1, {}, false, {}});
  client.wait_idle("tower", {}, std::chrono::seconds(120));

  // The raw echo server runs in its own process, as the daemon does (fork + exec: forking a
  // process that already runs DDS threads is unsafe). It answers with the daemon's own stats
  // reply, so both paths move samples of the same serialized size.
  const ispars::msg::QueryRequest stats_request = ispars::client::make_query(ispars::msg::STATS, "tower");
  const pid_t echo = ::fork();
  if (echo == 0) {
    const std::string domain = std::to_string(bench.domain);
    const std::string self = std::filesystem::canonical("/proc/self/exe").string();
    ::execl(self.c_str(), self.c_str(), "echo", "--domain", domain.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  RawEndpoints raw(bench.domain, "", "", false);
  for (int i = 0; !raw.matched(); ++i) {
    if (i > 3000) throw std::runtime_error("the raw echo server did not match within 30 s");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));

  std::vector<double> service, direct;
  ispars::msg::QueryRequest ping = stats_request;
  ping.client_id("raw");
  std::uint64_t seq = 0;
  for (int w = 0; w < 50; ++w) {  // warm-up, both paths
    (void)client.call(stats_request);
    ping.request_seq(++seq);
    (void)raw.round_trip(ping);
  }
  for (int block = 0; block < count / 100; ++block) {
    for (int i = 0; i < 100; ++i) {
      const auto t0 = Clock::now();
      (void)client.call(stats_request);
      service.push_back(seconds_since(t0));
    }
    for (int i = 0; i < 100; ++i) {
      ping.request_seq(++seq);
      direct.push_back(raw.round_trip(ping));
    }
  }
  ::kill(echo, SIGTERM);
  ::waitpid(echo, nullptr, 0);
  const double sm = percentile(service, 0.5) * 1e6, sp = percentile(service, 0.99) * 1e6;
  const double rm = percentile(direct, 0.5) * 1e6, rp = percentile(direct, 0.99) * 1e6;
  return {{"bench", "rtt"},
          {"round_trips", service.size()},
          {"service_median_us", sm},
          {"service_p99_us", sp},
          {"raw_median_us", rm},
          {"raw_p99_us", rp},
          {"median_ratio", sm / rm},
          {"p99_ratio", sp / rp}};
}

// The raw ping-pong's server side (a hidden subcommand run by `rtt`).
int run_echo(int domain) {
  ispars::client::ClientOptions options = ispars::client::local_client_options(domain);
  Client client(options);
  const ispars::msg::QueryRequest stats_request = ispars::client::make_query(ispars::msg::STATS, "tower");
  RawEndpoints server(domain, "", "", true);
  server.reply_template = client.call(stats_request);
  sigset_t stop;
  sigemptyset(&stop);
  sigaddset(&stop, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop, nullptr);
  int signal = 0;
  sigwait(&stop, &signal);
  return 0;
}

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
    control.build("tower", {method, samples, 1, {}, false, {}});
    const auto done = control.wait_idle("tower", {}, std::chrono::hours(1));
    const double build_seconds = seconds_since(t0);
    bool all_equal = true;
    for (auto& r : replicas) {
      r->wait_for(done.generation(), done.version(), std::chrono::seconds(120));
    }
    const double seconds = seconds_since(t0);
    const std::uint64_t digest = ispars::roadmap_digest(control.snapshot("tower").roadmap);
    std::size_t resyncs = 0;
    for (auto& r : replicas) {
      all_equal = all_equal && ispars::roadmap_digest(r->roadmap()) == digest;
      resyncs += r->snapshots_taken() - 1;
    }
    const double vertices = done.vertices();
    rows.push_back({{"subscribers", subscribers},
                    {"vertices", done.vertices()},
                    {"edges", done.edges()},
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
  client.build("tower", {"dense", vertices + vertices / 20, 1, {}, false, {}});
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
          {"vertices", done.vertices()},
          {"edges", done.edges()},
          {"bytes", bytes},
          {"median_seconds", percentile(times, 0.5)},
          {"max_seconds", percentile(times, 1.0)},
          {"megabytes_per_second", static_cast<double>(bytes) / 1e6 / percentile(times, 0.5)}};
}

std::size_t rss_kib(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stoul(line.substr(6));
  }
  return 0;
}

nlohmann::json run_memory(const std::string& daemon_binary, std::uint64_t samples) {
  nlohmann::json rows = nlohmann::json::array();
  for (const std::string method : {"dense", "ispars"}) {
    Bench bench(daemon_binary);
    Client client(bench.options());
    client.load("tower");
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::size_t before = rss_kib(bench.daemon->pid());
    client.build("tower", {method, samples, 1, {}, false, {}});
    const auto done = client.wait_idle("tower", {}, std::chrono::hours(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const std::size_t after = rss_kib(bench.daemon->pid());
    const double dense = method == "dense" ? done.vertices() : done.dense_vertices();
    rows.push_back({{"method", method},
                    {"samples", samples},
                    {"dense_vertices", dense},
                    {"dense_edges", method == "dense" ? done.edges() : done.dense_edges()},
                    {"sparse_vertices", method == "dense" ? 0u : done.vertices()},
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
  int echo_domain = 0;
  auto* echo = app.add_subcommand("echo", "")->group("");  // hidden: rtt's raw echo server
  echo->add_option("--domain", echo_domain);
  CLI11_PARSE(app, argc, argv);
  try {
    if (*echo) return run_echo(echo_domain);
    nlohmann::json out;
    if (*rtt) out = run_rtt(daemon, std::max(100, count));
    if (*stream) out = run_stream(daemon, samples, method);
    if (*snapshot) out = run_snapshot(daemon, vertices, repeats);
    if (*memory) out = run_memory(daemon, memory_samples);
    std::cout << out.dump() << std::endl;
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "ispars-bench: " << e.what() << "\n";
    return 1;
  }
}
