// A session's verify against the writers that must not wait for it.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ispars/params/input_error.hpp"
#include "roadmap_session_fixture.hpp"
#include "support/eventually.hpp"

namespace ispars::service {
namespace {

// Four readers looping verify never hold a writer up: the verifies running when a drop, then
// (after a rebuild) an unload starts are stopped naming why within half a second, the writer
// completes (its own work, closing the store, bounded loosely: a loaded CI machine took 1.2 s),
// and a verify over its budget is stopped naming the budget. (Before, overlapping verifies kept
// the job lock shared, and the drop failed as busy after 2 s.)
TEST_F(RoadmapSessionTest, LoopingVerifiesNeverHoldOffADropOrAnUnload) {
  auto session = open();
  session->request_build(ispars(busy_samples()));
  session->run_job(never_);
  try {
    (void)session->verify(std::chrono::milliseconds(1));
    ADD_FAILURE() << "a 1 ms budget was not enforced";
  } catch (const params::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("was stopped: its budget of 0.0 s ran out"), std::string::npos) << e.what();
  }
  std::atomic<bool> done{false};
  std::atomic<int> verified{0};
  std::mutex mutex;
  struct Stop {
    std::string why;
    std::chrono::steady_clock::time_point at;
  };
  std::vector<Stop> stops;  // running verifies stopped by a writer
  std::vector<std::jthread> readers;
  struct StopReaders {
    std::atomic<bool>& done;
    ~StopReaders() { done = true; }  // before the readers are joined, however the test ends
  } stop_readers{done};
  for (int i = 0; i < 4; ++i) {
    readers.emplace_back([&] {
      while (!done) {
        try {
          (void)session->verify(kVerifyBudget);
          ++verified;
        } catch (const params::InputError& e) {
          std::lock_guard lock(mutex);
          if (std::string(e.what()).find("was stopped") != std::string::npos) {
            stops.push_back({e.what(), std::chrono::steady_clock::now()});
          }
        }
      }
    });
  }
  const auto wait_for_verifies = [&](int n) {
    ASSERT_TRUE(test::eventually([&] { return verified >= n; }, std::chrono::seconds(30), "the verifies done",
                                 std::chrono::milliseconds(5)));
  };
  wait_for_verifies(8);
  const auto drop_at = std::chrono::steady_clock::now();
  session->drop();
  EXPECT_LT(std::chrono::steady_clock::now() - drop_at, std::chrono::seconds(5)) << "the drop waited for the verifies";
  EXPECT_EQ(session->status().state, SessionState::empty);
  session->request_build(ispars(busy_samples()));
  session->run_job(never_);
  const int before = verified;
  wait_for_verifies(before + 8);
  const auto unload_at = std::chrono::steady_clock::now();
  session->close();
  EXPECT_LT(std::chrono::steady_clock::now() - unload_at, std::chrono::seconds(5))
      << "the unload waited for the verifies";
  done = true;
  readers.clear();
  std::lock_guard lock(mutex);
  bool by_drop = false, by_unload = false;
  for (const auto& stop : stops) {
    const bool dropped = stop.why.find("scene 'tower' is being dropped") != std::string::npos;
    const bool unloaded = stop.why.find("scene 'tower' is being unloaded") != std::string::npos;
    if (dropped) {
      EXPECT_LT(stop.at - drop_at, std::chrono::milliseconds(500)) << "a verify ran on after the drop began";
    }
    if (unloaded) {
      EXPECT_LT(stop.at - unload_at, std::chrono::milliseconds(500)) << "a verify ran on after the unload began";
    }
    by_drop |= dropped;
    by_unload |= unloaded;
  }
  EXPECT_TRUE(by_drop || by_unload) << "no running verify was stopped (" << stops.size() << " stops)";
}

// A cancel request and a build starting on the scene stop a running verify too, each naming why.
TEST_F(RoadmapSessionTest, ACancelOrAStartingBuildStopsARunningVerify) {
  auto session = open();
  session->request_build(ispars(busy_samples()));
  session->run_job(never_);
  // Runs `writer` while a verify runs (tried until one was caught running); the verify's error.
  const auto stopped_by = [&](const std::function<void()>& writer) {
    for (int attempt = 0; attempt < 50; ++attempt) {
      std::string error;
      std::atomic<bool> started{false};
      std::jthread reader([&] {
        started = true;
        try {
          (void)session->verify(kVerifyBudget);
        } catch (const params::InputError& e) {
          error = e.what();
        }
      });
      while (!started) std::this_thread::yield();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      writer();
      reader.join();
      if (error.find("was stopped") != std::string::npos) return error;
    }
    return std::string("no verify was caught running");
  };
  EXPECT_NE(
      stopped_by([&] { (void)session->cancel(); }).find("was stopped: cancelled by a cancel request on scene 'tower'"),
      std::string::npos);
  std::jthread job;
  const std::string by_build = stopped_by([&] {
    session->request_extend(200);
    job = std::jthread([&] { session->run_job(never_); });
    job.join();
  });
  EXPECT_NE(by_build.find("was stopped: a build started on scene 'tower'"), std::string::npos) << by_build;
}

}  // namespace
}  // namespace ispars::service
