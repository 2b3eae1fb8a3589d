#include "stoppable.hpp"

#include <condition_variable>
#include <deque>

namespace ispars::python {
namespace {

// The call threads: made on demand, never destroyed (the process's exit ends them; a thread
// joined or destroyed at exit could still be in a call whose request waits on a daemon).
class CallThreads {
 public:
  void post(std::function<void()> task) {
    std::unique_lock lock(mutex_);
    tasks_.push_back(std::move(task));
    if (idle_ > 0) {
      --idle_;
      ready_.notify_one();
      return;
    }
    lock.unlock();
    std::thread([this] { serve(); }).detach();
  }

 private:
  static constexpr int kMaxIdle = 4;

  void serve() {
    std::unique_lock lock(mutex_);
    for (;;) {
      while (!tasks_.empty()) {
        std::function<void()> task = std::move(tasks_.front());
        tasks_.pop_front();
        lock.unlock();
        task();
        task = nullptr;  // what it holds is released before the thread waits again
        lock.lock();
      }
      if (idle_ >= kMaxIdle) return;
      ++idle_;
      ready_.wait(lock, [this] { return !tasks_.empty(); });
    }
  }

  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> tasks_;
  int idle_ = 0;
};

}  // namespace

void post_call(std::function<void()> task) {
  static CallThreads* const threads = new CallThreads();  // never destroyed: see CallThreads
  threads->post(std::move(task));
}

}  // namespace ispars::python
