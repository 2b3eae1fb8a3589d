// Integration tests of the daemon's limits: slow requests never hold back STATS, a lane past its
// bound refuses at once (busy) instead of queueing without end, and builds that would exhaust
// memory are refused before they start.

#include <atomic>
#include <chrono>
#include <optional>
#include <thread>

#include <fstream>

#include "integration/service_fixture.hpp"
#include "support/raw_peer.hpp"

namespace ispars::test {
namespace {

TEST_F(ServiceTest, SlowRequestsNeverHoldBackStatsAndAFullLaneAnswersBusy) {
  // Two slow threads and room for two waiting: of eight verifies sent at once, at least one is
  // refused as busy, and a STATS sent behind them is answered before any verify.
  auto daemon = start("d", {"--request-queue", "2"});
  Client control(client_options(domain_));
  control.load("s0");
  control.build("s0", ispars_build(20'000));
  (void)control.wait_idle("s0", {}, kLong);
  constexpr int kVerifies = 8;
  std::vector<std::unique_ptr<Client>> clients;
  for (int i = 0; i < kVerifies; ++i) {
    clients.push_back(std::make_unique<Client>(client_options(domain_)));
    (void)clients.back()->stats("s0");  // discovered and matched before the burst
  }
  using Clock = std::chrono::steady_clock;
  std::vector<msg::Reply> replies(kVerifies);
  std::vector<Clock::time_point> answered_at(kVerifies);
  std::vector<std::jthread> threads;  // joined however the test ends
  std::atomic<bool> go{false};
  for (int i = 0; i < kVerifies; ++i) {
    threads.emplace_back([&, i] {
      while (!go) std::this_thread::yield();
      const auto k = static_cast<std::size_t>(i);
      try {
        replies[k] = call_raw(*clients[k], make_query(msg::VERIFY, "s0"), "d");
      } catch (const ClientError& e) {  // a failure, not the end of the test process
        replies[k].ok(false);
        replies[k].error(std::string("no reply: ") + e.what());
      }
      answered_at[k] = Clock::now();
    });
  }
  go = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  SceneStatus status;
  std::string stats_error;
  try {
    status = control.stats("s0");
  } catch (const ClientError& e) {
    stats_error = e.what();
  }
  const Clock::time_point stats_at = Clock::now();
  for (auto& t : threads) t.join();
  EXPECT_EQ(stats_error, "") << "STATS was refused behind the verifies";
  EXPECT_EQ(status.state, SceneState::idle);
  int verified = 0, busy = 0;
  Clock::time_point first_verified = Clock::time_point::max();
  for (int i = 0; i < kVerifies; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (replies[k].ok()) {
      EXPECT_EQ(replies[k].body().verify().violations(), 0u);
      first_verified = std::min(first_verified, answered_at[k]);
      ++verified;
    } else {
      EXPECT_NE(replies[k].error().find("request: kind: busy: 2 requests are queued on this daemon's slow lane"),
                std::string::npos)
          << replies[k].error();
      ++busy;
    }
  }
  EXPECT_GE(verified, 2);
  EXPECT_GE(busy, 1) << "eight verifies fitted in a lane of two threads and two places";
  EXPECT_LT(stats_at, first_verified) << "STATS waited behind a verify";
  EXPECT_NE(daemon->log().find("refused: the slow lane holds 2 requests"), std::string::npos);
  EXPECT_TRUE(daemon->alive());
}

TEST_F(ServiceTest, ExhaustionAttemptsAreRefusedBeforeMemoryGrows) {
  auto daemon = start("d");  // the default budget: half of this machine's memory
  Client client(client_options(domain_));
  client.load("s0");
  const auto refused = [&](std::uint64_t samples, std::optional<double> dense_delta) {
    msg::ChangeRequest r = make_change(msg::BUILD, "s0");
    r.args().build().method("ispars");
    r.args().build().samples(samples);
    if (dense_delta) {
      r.args().build().overrides().dense_delta(*dense_delta);
      r.args().build().overrides().present(1);  // bit 0: dense_delta
    }
    const msg::Reply reply = call_raw(client, r, "d");
    EXPECT_FALSE(reply.ok()) << samples;
    EXPECT_NE(reply.error().find("more than this daemon's memory budget leaves"), std::string::npos) << reply.error();
  };
  refused(100'000, 1e6);     // every pair within delta: about 10^10 edges
  refused(50'000'000, {});   // the most samples a request may ask for
  refused(40'000'000, 0.1);  // a tiny delta does not save a huge N
  EXPECT_EQ(client.stats("s0").state, SceneState::empty) << "a refusal changed the scene";
  client.build("s0", ispars_build(2000));
  const auto built = client.wait_idle("s0", {}, kLong);
  // Thousands of requests at once from raw writers: the slow lane holds 256, the rest are
  // refused as busy, and the daemon keeps answering.
  std::vector<std::unique_ptr<RawPeer>> peers;
  for (int p = 0; p < 4; ++p) peers.push_back(std::make_unique<RawPeer>(domain_));
  for (int i = 0; i < 500; ++i) {
    for (auto& peer : peers) {
      msg::QueryRequest r = make_query(msg::VERIFY, "s0");
      r.server_id("d");
      r.request_seq(static_cast<std::uint64_t>(i) + 1);
      r.protocol(msg::PROTOCOL_VERSION);
      ASSERT_TRUE(peer->post(r));
    }
  }
  EXPECT_EQ(client.stats("s0").samples_done, built.samples_done);
  std::size_t received = 0, last = 0;
  for (int quiet = 0; quiet < 20 && received < 2000; ++quiet) {  // until 2 s pass without a reply
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    received = 0;
    for (const auto& peer : peers) received += peer->replies_received();
    if (received != last) quiet = 0;
    last = received;
  }
  std::size_t busy = 0, verified = 0;
  for (const auto& peer : peers) {
    for (const msg::Reply& r : peer->replies()) {
      if (r.ok()) {
        ++verified;
      } else if (r.error().find("request: kind: busy: 256 requests are queued on this daemon's slow lane") !=
                 std::string::npos) {
        ++busy;
      } else {
        ADD_FAILURE() << r.error();
      }
    }
  }
  EXPECT_GE(busy, 1u) << "2000 verifies at once fitted in a lane of 256";
  EXPECT_GE(verified, 1u);
  EXPECT_TRUE(daemon->alive());
  const double peak = peak_rss_mib(daemon->pid());
  std::printf("daemon peak RSS after the attempts: %.1f MiB; %zu verified, %zu busy of %zu replies\n", peak, verified,
              busy, received);
  EXPECT_LT(peak, 512.0) << "memory grew under the attempts";
  const auto after = client.stats("s0");
  EXPECT_EQ(after.samples_done, built.samples_done);
  EXPECT_EQ(after.version, built.version);
}

}  // namespace
}  // namespace ispars::test
