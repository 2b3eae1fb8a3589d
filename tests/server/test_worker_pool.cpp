// The build worker pool: jobs run concurrently up to the thread count; stop waits for them.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "ispars/service/worker_pool.hpp"
#include "support/eventually.hpp"

namespace ispars::service {
namespace {

using namespace std::chrono_literals;
using test::eventually;

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
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the job's own work
        --running;
        ++done;
      });
    }
    ASSERT_TRUE(eventually([&] { return done == 6; }, 10s, "six jobs done", 1ms));
  }
  EXPECT_EQ(done.load(), 6);
  EXPECT_LE(peak.load(), 2);
  EXPECT_GE(peak.load(), 1);
}

TEST(WorkerPool, StopDropsQueuedJobsAndRefusesNewOnes) {
  std::atomic<int> done{0};
  std::atomic<bool> started{false};
  std::promise<void> release;
  WorkerPool pool(1);
  pool.submit([&, released = release.get_future().share()] {
    started = true;
    released.wait();
    ++done;
  });
  pool.submit([&] { ++done; });  // queued behind the first
  // stop() must find the first job running (a loaded machine may not have started it yet).
  ASSERT_TRUE(eventually([&] { return started.load(); }, 10s, "the first job starts", 1ms));
  std::thread stopper([&] { pool.stop(); });
  // The first job holds the only thread, so the queue empties only when stop() drops the second
  // (a fixed wait here let a loaded machine release the first before stop() began).
  EXPECT_TRUE(eventually([&] { return pool.queued() == 0; }, 10s, "stop() drops the queued job", 1ms));
  release.set_value();
  stopper.join();
  EXPECT_EQ(done.load(), 1);
  pool.submit([&] { ++done; });
  EXPECT_EQ(done.load(), 1);
}

TEST(WorkerPool, ABoundedQueueRefusesPastItsLimitAndAcceptsAgainOnceItDrains) {
  std::atomic<bool> started{false};
  std::promise<void> release;
  std::atomic<int> done{0};
  WorkerPool pool(1, /*max_queued=*/2);
  ASSERT_TRUE(pool.submit([&, released = release.get_future().share()] {
    started = true;
    released.wait();
    ++done;
  }));
  ASSERT_TRUE(eventually([&] { return started.load(); }, 10s, "the first job starts", 1ms));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  EXPECT_EQ(pool.queued(), 2u);
  EXPECT_FALSE(pool.submit([&] { ++done; })) << "a third job waited past the bound";
  release.set_value();
  ASSERT_TRUE(eventually([&] { return done == 3; }, 10s, "three jobs done", 1ms));
  EXPECT_TRUE(pool.submit([&] { ++done; }));
  ASSERT_TRUE(eventually([&] { return done == 4; }, 10s, "four jobs done", 1ms));
  pool.stop();
  EXPECT_EQ(done.load(), 4);
}

}  // namespace
}  // namespace ispars::service
