// Reply routes against a real daemon: a client's route opens when its reply reader is discovered,
// before any request; a first reply reaches a fresh client with no resend; a fresh client's first
// tour reports progress; and routes held follow the clients that are present, however many came
// and went (more than the bound of 256).

#include <algorithm>
#include <cstdio>
#include <deque>
#include <thread>

#include "integration/service_fixture.hpp"
#include "ispars/wire/convert.hpp"
#include "support/raw_peer.hpp"

#include <httplib.h>  // after Eigen (service_fixture.hpp): it defines a macro Eigen's headers use

namespace ispars::test {
namespace {

// The value of metric `series` served on `port`; -1 when absent or unreachable.
double metric(int port, const std::string& series) {
  httplib::Client http("127.0.0.1", port);
  http.set_read_timeout(5, 0);
  const auto res = http.Get("/metrics");
  if (!res || res->status != 200) return -1;
  const std::string text = "\n" + res->body;
  const auto at = text.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::stod(text.substr(at + series.size() + 2));
}

// Polls metric `series` until it equals `want` (at most `within`); returns the last value read.
double await_metric(int port, const std::string& series, double want, std::chrono::milliseconds within) {
  double value = 0.0;
  (void)eventually(
      [&] {
        value = metric(port, series);
        return value == want;
      },
      within, series, std::chrono::milliseconds(100));
  return value;
}

msg::QueryRequest stats_request(std::uint64_t seq) {
  msg::QueryRequest stats = client::make_query(msg::STATS, "s0");
  stats.server_id("d");
  stats.protocol(msg::PROTOCOL_VERSION);
  stats.request_seq(seq);
  return stats;
}

TEST_F(ServiceTest, ARouteOpensWhenTheReplyReaderIsDiscoveredBeforeAnyRequest) {
  auto daemon = start("d");
  RawPeer peer(domain_);
  EXPECT_TRUE(eventually([&] { return peer.route_opens() > 0; }, std::chrono::seconds(10),
                         "a route-open reply before any request", std::chrono::milliseconds(10)));
  EXPECT_EQ(peer.route_opens(), 1u);
  // request_seq 0 is the route-open reply's: a request with it is refused by name.
  ASSERT_TRUE(peer.post(stats_request(0)));
  EXPECT_TRUE(eventually([&] { return peer.route_opens() == 2; }, std::chrono::seconds(5), "the refusal's route-open",
                         std::chrono::milliseconds(10)));
  EXPECT_NE(daemon->log().find("request_seq: 0 is reserved"), std::string::npos) << daemon->log();
}

// 300 fresh clients one after another, each posting one STATS with no resend and waiting 2 s:
// every first reply arrives. Five stay; when the others have left, the daemon holds five routes.
TEST_F(ServiceTest, ThreeHundredClientsComeAndGoAndTheRoutesHeldAreThoseOfTheLiveOnes) {
  auto daemon = start("d", {"--metrics", "127.0.0.1:0"});
  const int port = metrics_port(daemon->log());
  ASSERT_GT(port, 0) << daemon->log();
  Client c(client_options(domain_));
  c.load("s0");
  constexpr int kClients = 300;
  constexpr std::size_t kStaying = 5;
  std::deque<std::unique_ptr<RawPeer>> live;
  int lost = 0;
  std::vector<double> latency_ms;
  for (int i = 0; i < kClients; ++i) {
    live.push_back(std::make_unique<RawPeer>(domain_));
    RawPeer& peer = *live.back();
    ASSERT_TRUE(peer.post(stats_request(1))) << "client " << i << " never matched the daemon";
    const auto posted = std::chrono::steady_clock::now();
    (void)eventually([&] { return peer.replies_to(1) > 0; }, std::chrono::seconds(2), "an answer",
                     std::chrono::milliseconds(5));  // counted below
    if (peer.replies_to(1) == 0) {
      ++lost;
    } else {
      latency_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - posted).count());
    }
    if (live.size() > kStaying) live.pop_front();
  }
  EXPECT_EQ(lost, 0) << "first replies lost of " << kClients;
  std::sort(latency_ms.begin(), latency_ms.end());
  if (!latency_ms.empty()) {
    std::printf("first reply after the post, ms (%zu clients): min %.1f median %.1f p95 %.1f max %.1f\n",
                latency_ms.size(), latency_ms.front(), latency_ms[latency_ms.size() / 2],
                latency_ms[latency_ms.size() * 95 / 100], latency_ms.back());
  }
  // The staying five and the C++ client above hold a route each; the 295 that left hold none.
  EXPECT_EQ(await_metric(port, "ispars_reply_routes", kStaying + 1, std::chrono::seconds(15)), kStaying + 1);
  EXPECT_EQ(metric(port, "ispars_reply_clients"), kStaying + 1);
  live.clear();
  EXPECT_EQ(await_metric(port, "ispars_reply_routes", 1, std::chrono::seconds(15)), 1);
}

TEST_F(ServiceTest, AFreshClientsFirstTourReportsProgress) {
  auto daemon = start("d");
  {
    Client builder(client_options(domain_));
    builder.load("s0");
    builder.build("s0", ispars_build(1500));
    (void)builder.wait_idle("s0", {}, kLong);
  }
  Client fresh(client_options(domain_));
  int progress = 0;
  const auto reply = fresh.tour("s0", 2.0, 1, {}, [&](double, double, double) { ++progress; });
  EXPECT_TRUE(reply.tour.valid);
  EXPECT_GT(progress, 0) << "the first tour of a fresh client reported no progress";
}

}  // namespace
}  // namespace ispars::test
