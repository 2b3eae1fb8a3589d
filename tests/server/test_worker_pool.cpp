// The build worker pool: jobs run concurrently up to the thread count; stop waits for them.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "ispars/service/worker_pool.hpp"

namespace ispars::server {
namespace {

TEST(WorkerPool, RunsJobsOnItsThreadsAndStopWaitsForRunningOnes) {
  std::atomic<int> running{0}, peak{0}, done{0};
  {
    WorkerPool pool(2);
    for (int i = 0; i < 6; ++i) {
      pool.submit([&] {
        const int now = ++running;
        int p = peak.load();
        while (now > p && !peak.compare_exchange_weak(p, now)) {
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        --running;
        ++done;
      });
    }
    while (done < 6) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(done.load(), 6);
  EXPECT_LE(peak.load(), 2);
  EXPECT_GE(peak.load(), 1);
}

TEST(WorkerPool, StopDropsQueuedJobsAndRefusesNewOnes) {
  std::atomic<int> done{0};
  std::atomic<bool> release{false}, started{false};
  WorkerPool pool(1);
  pool.submit([&] {
    started = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ++done;
  });
  pool.submit([&] { ++done; });  // queued behind the first
  // stop() must find the first job running (a loaded machine may not have started it yet).
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::thread stopper([&] { pool.stop(); });
  // The first job holds the only thread, so the queue empties only when stop() drops the second
  // (a fixed wait here let a loaded machine release the first before stop() began).
  while (pool.queued() != 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  release = true;
  stopper.join();
  EXPECT_EQ(done.load(), 1);
  pool.submit([&] { ++done; });
  EXPECT_EQ(done.load(), 1);
}

TEST(WorkerPool, ABoundedQueueRefusesPastItsLimitAndAcceptsAgainOnceItDrains) {
  std::atomic<bool> release{false}, started{false};
  std::atomic<int> done{0};
  WorkerPool pool(1, /*max_queued=*/2);
  ASSERT_TRUE(pool.submit([&] {
    started = true;
    while (!release) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ++done;
  }));
  while (!started) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  EXPECT_EQ(pool.queued(), 2u);
  EXPECT_FALSE(pool.submit([&] { ++done; })) << "a third job waited past the bound";
  release = true;
  while (done < 3) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  while (done < 4) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  pool.stop();
  EXPECT_EQ(done.load(), 4);
}

}  // namespace
}  // namespace ispars::server
