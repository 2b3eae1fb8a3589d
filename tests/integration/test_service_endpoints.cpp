// What an operator's tools see of a running daemon: systemd's notifications (READY, WATCHDOG,
// STOPPING) on the socket the service manager names, and the /metrics and /healthz endpoint.

#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "integration/service_fixture.hpp"

// After Eigen (through the fixture): httplib pulls in OpenSSL, whose macros upset Eigen's headers.
#include <httplib.h>

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;

// A service manager's notification socket: a datagram socket bound at a path.
class NotifySocket {
 public:
  explicit NotifySocket(const std::filesystem::path& path) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof(address.sun_path), "%s", path.c_str());
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
      throw std::runtime_error("cannot bind " + path.string());
    }
    timeval timeout{0, 100'000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof(timeout));
  }
  ~NotifySocket() { ::close(fd_); }
  // Every datagram received until `until` holds or `limit` passes.
  std::vector<std::string> receive(std::chrono::milliseconds limit,
                                   const std::function<bool(const std::vector<std::string>&)>& until) {
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline && !until(messages_)) {
      char buffer[4096];
      const ssize_t n = ::recv(fd_, buffer, sizeof(buffer), 0);
      if (n > 0) messages_.emplace_back(buffer, static_cast<std::size_t>(n));
    }
    return messages_;
  }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::vector<std::string> messages_;
};

std::size_t count_of(const std::vector<std::string>& messages, const std::string& text) {
  return static_cast<std::size_t>(std::count_if(
      messages.begin(), messages.end(), [&](const std::string& m) { return m.find(text) != std::string::npos; }));
}

TEST_F(ServiceTest, SystemdHearsReadyThenWatchdogPingsThenStopping) {
  NotifySocket manager(dir_.path() / "notify.sock");
  // What systemd sets for a Type=notify unit with WatchdogSec=0.4, in the daemon's process only.
  auto daemon = std::make_unique<DaemonProcess>(
      ISPARS_DAEMON, domain_, dir_.path() / "data-d", scene_dir_, "d", std::vector<std::string>{}, "",
      std::vector<std::string>{"NOTIFY_SOCKET=" + (dir_.path() / "notify.sock").string(), "WATCHDOG_USEC=400000"});
  // Pings every 200 ms (half the timeout): at least 4 in 1.5 s after READY.
  auto messages =
      manager.receive(std::chrono::seconds(10), [](const auto& m) { return count_of(m, "WATCHDOG=1") >= 4; });
  ASSERT_FALSE(messages.empty());
  EXPECT_NE(messages.front().find("READY=1\nSTATUS=serving on DDS domain"), std::string::npos) << messages.front();
  EXPECT_GE(count_of(messages, "WATCHDOG=1"), 4u);
  EXPECT_EQ(count_of(messages, "STOPPING=1"), 0u);
  ASSERT_EQ(::kill(daemon->pid(), SIGHUP), 0);
  messages = manager.receive(std::chrono::seconds(5), [](const auto& m) { return count_of(m, "READY=1") >= 2; });
  EXPECT_EQ(count_of(messages, "RELOADING=1"), 1u);
  EXPECT_EQ(count_of(messages, "READY=1"), 2u) << "READY again after the reload";
  EXPECT_EQ(daemon->terminate(), 0);
  messages = manager.receive(std::chrono::seconds(2), [](const auto& m) { return count_of(m, "STOPPING=1") >= 1; });
  EXPECT_EQ(count_of(messages, "STOPPING=1"), 1u);
}

// The value of metric line `series` (name and labels, exactly) in an exposition; -1 when absent.
double metric(const std::string& text, const std::string& series) {
  const auto at = text.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::stod(text.substr(at + series.size() + 2));
}

TEST_F(ServiceTest, MetricsCountRequestsByOutcomeAndShowEachRoadmapAsStatsDoes) {
  auto daemon = start("d", {"--metrics", "127.0.0.1:0"});
  const int port = metrics_port(daemon->log());
  ASSERT_GT(port, 0) << daemon->log();
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(5, 0);

  Client c(client_options(domain_));
  const SceneStatus built = load_and_build(c, "s0", ispars_build(1500));
  for (int i = 0; i < 3; ++i) (void)c.stats("s0");
  EXPECT_THROW((void)c.stats("nowhere"), ClientError);

  const auto res = http.Get("/metrics");
  ASSERT_TRUE(res) << "no answer on port " << port;
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  const std::string text = "\n" + res->body;
  EXPECT_EQ(metric(text, "ispars_requests_total{operation=\"load\",outcome=\"ok\"}"), 1);
  EXPECT_EQ(metric(text, "ispars_requests_total{operation=\"build\",outcome=\"ok\"}"), 1);
  EXPECT_GE(metric(text, "ispars_requests_total{operation=\"stats\",outcome=\"ok\"}"), 3);
  EXPECT_EQ(metric(text, "ispars_requests_total{operation=\"stats\",outcome=\"refused\"}"), 1);
  // The histogram is cumulative and its +Inf bucket is the count.
  const double stats_count = metric(text, "ispars_request_duration_seconds_count{operation=\"stats\"}");
  EXPECT_EQ(metric(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"+Inf\"}"), stats_count);
  EXPECT_LE(metric(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"0.001\"}"),
            metric(text, "ispars_request_duration_seconds_bucket{operation=\"stats\",le=\"0.01\"}"));
  EXPECT_EQ(metric(text, "ispars_samples_built_total"), 1500);
  EXPECT_EQ(metric(text, "ispars_scenes{state=\"idle\"}"), 1);
  EXPECT_EQ(metric(text, "ispars_roadmap_vertices{scene=\"s0\"}"), static_cast<double>(built.vertices));
  EXPECT_EQ(metric(text, "ispars_roadmap_edges{scene=\"s0\"}"), static_cast<double>(built.edges));
  EXPECT_GT(metric(text, "process_resident_memory_bytes"), 1e6);
  // The built roadmap reserves its estimated peak of the budget; nothing runs that leases any.
  EXPECT_GT(metric(text, "ispars_memory_reserved_bytes"), 0);
  EXPECT_EQ(metric(text, "ispars_memory_leased_bytes"), 0);

  const auto health = http.Get("/healthz");
  ASSERT_TRUE(health);
  EXPECT_EQ(health->status, 200);
  EXPECT_EQ(health->body, "ok\n");
  const auto post = http.Post("/metrics", "x", "text/plain");
  ASSERT_TRUE(post);
  EXPECT_EQ(post->status, 405);
  const auto elsewhere = http.Get("/admin");
  ASSERT_TRUE(elsewhere);
  EXPECT_EQ(elsewhere->status, 404);

  EXPECT_EQ(daemon->terminate(), 0);
  EXPECT_FALSE(http.Get("/healthz")) << "the endpoint outlived the daemon";
}

TEST_F(ServiceTest, AMetricsPortInUseStopsTheStartNamingIt) {
  auto first = start("first", {"--metrics", "127.0.0.1:0"});
  const int port = metrics_port(first->log());
  ASSERT_GT(port, 0);
  try {
    DaemonProcess second(ISPARS_DAEMON, domain_, dir_.path() / "data-second", scene_dir_, "second",
                         {"--metrics", "127.0.0.1:" + std::to_string(port)});
    ADD_FAILURE() << "a second daemon started on a metrics port in use:\n" << second.log();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("metrics: cannot listen on 127.0.0.1:" + std::to_string(port)),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(first->alive());
}

}  // namespace
}  // namespace ispars::test
