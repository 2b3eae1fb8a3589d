#pragma once
// A fixed pool of threads running queued jobs: the daemon's requests, builds and tours.

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

namespace ispars::service {

/// Runs submitted jobs in order on a fixed number of threads.
class WorkerPool {
 public:
  /// `threads` threads; at most `max_queued` jobs wait for one (submit refuses past that).
  explicit WorkerPool(unsigned threads, std::size_t max_queued = std::numeric_limits<std::size_t>::max());
  /// Finishes the running jobs (queued ones are dropped) and joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  /// Queues `job` (ahead of every waiting job when `first`); false (and the job dropped) when
  /// the pool is stopping or its queue is full.
  bool submit(std::function<void()> job, bool first = false);
  /// Jobs waiting for a thread.
  [[nodiscard]] std::size_t queued() const;
  [[nodiscard]] std::size_t max_queued() const { return max_queued_; }
  /// Jobs finished so far: a pool whose count stops moving while jobs wait is wedged.
  [[nodiscard]] std::uint64_t completed() const { return completed_.load(std::memory_order_relaxed); }
  /// Stops taking jobs, drops the queued ones, and waits for the running ones.
  void stop();

 private:
  void run();
  const std::size_t max_queued_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::atomic<std::uint64_t> completed_{0};
  std::vector<std::thread> threads_;
};

}  // namespace ispars::service
