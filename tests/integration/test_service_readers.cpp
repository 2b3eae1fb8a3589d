// Readers never stall the daemon: eight viewers loop VERIFY and SNAPSHOT on two 100,000-sample
// roadmaps while an operator unloads and loads one, drops the other, and stops the daemon. Each
// writer completes within its bound, STATS of a third scene stays fast, and SIGTERM ends the
// daemon within 2 s.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "integration/service_fixture.hpp"

namespace ispars::test {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

TEST_F(ServiceTest, LoopingViewersNeverHoldUpAnUnloadADropOrTheStop) {
  constexpr double kWriterBound = 2.0;  // seconds an operator's unload or drop may take here
  auto daemon = start("d", {"--memory-budget-mb", kNoBudget});
  Client op(client_options(domain_));
  for (const char* scene : {"s0", "s1", "s2"}) op.load(scene);
  op.build("s0", ispars_build(scaled(100'000)));
  op.build("s2", ispars_build(scaled(100'000)));
  ASSERT_EQ(op.wait_idle("s0", {}, std::chrono::seconds(600)).state, SceneState::idle);
  ASSERT_EQ(op.wait_idle("s2", {}, std::chrono::seconds(600)).state, SceneState::idle);
  op.build("s1", ispars_build(2000));
  ASSERT_EQ(op.wait_idle("s1", {}, kLong).state, SceneState::idle);

  std::atomic<bool> done{false};
  std::atomic<int> verifies{0}, snapshots{0};
  std::vector<std::jthread> viewers;
  struct StopViewers {
    std::atomic<bool>& done;
    ~StopViewers() { done = true; }  // before the viewers are joined, however the test ends
  } stop_viewers{done};
  for (int i = 0; i < 8; ++i) {
    viewers.emplace_back([&, i] {
      Client viewer(client_options(domain_));
      const char* scene = i % 4 < 2 ? "s0" : "s2";
      while (!done) {
        try {
          if (i % 2 == 0) {
            if (call_raw(viewer, make_query(msg::VERIFY, scene), "d").ok()) {
              ++verifies;
            } else {
              std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
          } else {
            (void)viewer.snapshot(scene);
            ++snapshots;
          }
        } catch (const std::exception&) {
          // unloaded, dropped, stopped or busy meanwhile: a viewer asks again a moment later
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
      }
    });
  }
  // STATS of the other scene, every 20 ms, all along.
  std::vector<double> stats_ms;
  std::mutex stats_mutex;
  std::atomic<bool> probing{true};
  std::jthread prober([&] {
    while (probing && !done) {
      const auto t0 = Clock::now();
      try {
        (void)op.stats("s1");
        std::lock_guard lock(stats_mutex);
        stats_ms.push_back(seconds_since(t0) * 1000.0);
      } catch (const std::exception&) {
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  // The viewers at work: they loop without pause, and a verify of this roadmap takes longer than
  // this (the daemon's log then shows each writer stopping the verifies it met, by name).
  const auto wait_for_viewers = [] { std::this_thread::sleep_for(std::chrono::seconds(3)); };  // work, not a wait
  wait_for_viewers();
  // The stopped verify's answer is logged as its request ends, a moment after the writer's.
  const auto log_has = [&](const std::string& text) {
    return eventually([&] { return daemon->log().find(text) != std::string::npos; }, std::chrono::seconds(2),
                      "the log says: " + text);
  };

  // Unloaded until an unload meets a running verify (on a loaded machine the viewers' verifies
  // may all be waiting in the lane at that moment); every unload within the bound.
  double unload_s = 0.0;
  bool met_a_verify = false;
  for (int attempt = 0; attempt < 5 && !met_a_verify; ++attempt) {
    const auto t0 = Clock::now();
    op.unload("s0");
    unload_s = std::max(unload_s, seconds_since(t0));
    EXPECT_LT(seconds_since(t0), kWriterBound) << "UNLOAD waited for the viewers";
    met_a_verify = log_has("was stopped: scene 's0' is being unloaded");
    op.load("s0");  // the stored roadmap comes back
    wait_for_viewers();
  }
  // Whether a writer met a running verify depends on which requests hold the two lane threads at
  // that moment: reported, not asserted (the session and service tests assert it exactly).
  auto t0 = Clock::now();
  op.drop("s2");
  const double drop_s = seconds_since(t0);
  EXPECT_LT(drop_s, kWriterBound) << "DROP waited for the viewers";
  const bool drop_met = log_has("was stopped: scene 's2' is being dropped");
  wait_for_viewers();
  probing = false;
  prober = {};
  t0 = Clock::now();
  EXPECT_EQ(daemon->terminate(), 0);
  const double stop_s = seconds_since(t0);
  EXPECT_LT(stop_s, 2.0) << "SIGTERM waited for the viewers";
  const bool stop_met = daemon->log().find("was stopped: the daemon is stopping") != std::string::npos;
  done = true;
  std::lock_guard lock(stats_mutex);
  ASSERT_GE(stats_ms.size(), 20u);
  std::sort(stats_ms.begin(), stats_ms.end());
  const double p99 = stats_ms[stats_ms.size() * 99 / 100];
  EXPECT_LT(p99, 50.0) << "STATS of another scene waited behind the viewers";
  std::printf(
      "viewers: %d verifies, %d snapshots; unload %.3f s, drop %.3f s, stop %.3f s; STATS of s1 p99 %.1f ms "
      "(median %.1f, %zu probes); a running verify met by the unload %d, the drop %d, the stop %d\n",
      verifies.load(), snapshots.load(), unload_s, drop_s, stop_s, p99, stats_ms[stats_ms.size() / 2], stats_ms.size(),
      met_a_verify, drop_met, stop_met);
}

}  // namespace
}  // namespace ispars::test
