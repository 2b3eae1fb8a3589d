#pragma once
// A fixed pool of threads running queued jobs: the daemon's requests, builds and tours.

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ispars::server {

/// Runs submitted jobs in order on a fixed number of threads.
class WorkerPool {
 public:
  explicit WorkerPool(unsigned threads);
  /// Finishes the running jobs (queued ones are dropped) and joins the threads.
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  void submit(std::function<void()> job);
  /// Stops taking jobs, drops the queued ones, and waits for the running ones.
  void stop();

 private:
  void run();
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace ispars::server
