#pragma once
// Long calls from Python: run without the GIL, on a worker thread, while the calling thread
// watches for Ctrl-C (the interpreter's pending signals) and for the caller's ispars.Stop every
// 20 ms. Python callbacks run on the worker with the GIL taken for each call; an exception one
// raises stops the work and is raised again to the caller.

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>

#include "python_module.hpp"

namespace ispars::python {

/// Seconds of wall time since `t0`.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// ispars.Stop: a flag any thread may set to stop the long calls it was given to.
struct StopFlag {
  std::atomic<bool> set{false};
};

/// What a worker and its watcher share: the halt the work reads, and the first exception a
/// Python callback raised.
class Halt {
 public:
  [[nodiscard]] const std::atomic<bool>& flag() const { return halt_; }
  [[nodiscard]] bool halted() const { return halt_.load(); }
  void halt() { halt_ = true; }
  /// Keeps the current exception (a callback's), the first one only, and halts.
  void fail() {
    std::lock_guard lock(mutex_);
    if (!error_) error_ = std::current_exception();
    halt_ = true;
  }
  void rethrow() const {
    std::lock_guard lock(mutex_);
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::atomic<bool> halt_{false};
  mutable std::mutex mutex_;
  std::exception_ptr error_;
};

/// A Python callable held by C++ threads: copied and destroyed without the GIL, called with it.
/// An exception it raises is kept in `halt` (which then halts) and not raised on that thread.
class Callback {
 public:
  Callback() = default;
  Callback(const py::object& f, std::shared_ptr<Halt> halt)
      : f_(f.is_none() ? nullptr : new py::object(f),
           [](py::object* p) {
             if (p == nullptr) return;
             py::gil_scoped_acquire gil;
             delete p;
           }),
        halt_(std::move(halt)) {}
  explicit operator bool() const { return f_ != nullptr; }
  template <class... A>
  void operator()(A... args) const {
    if (!f_ || halt_->halted()) return;
    py::gil_scoped_acquire gil;
    try {
      (*f_)(args...);
    } catch (...) {
      halt_->fail();
    }
  }

 private:
  std::shared_ptr<py::object> f_;
  std::shared_ptr<Halt> halt_;
};

/// Runs `work` on a worker thread and waits, without the GIL, until it ends. Ctrl-C or `stop`
/// halts `halt` (which `work` must read and end on within its own latency); Ctrl-C then raises
/// KeyboardInterrupt once `work` has ended. A callback's exception is raised after `work` ends.
template <class F>
auto run_stoppable(F work, Halt& halt, const StopFlag* stop) -> decltype(work()) {
  using R = decltype(work());
  std::packaged_task<R()> task(std::move(work));
  std::future<R> result = task.get_future();
  std::thread worker(std::move(task));
  bool interrupted = false;
  for (;;) {
    std::future_status status;
    {
      py::gil_scoped_release release;
      status = result.wait_for(std::chrono::milliseconds(20));
    }
    if (status == std::future_status::ready) break;
    if (stop != nullptr && stop->set.load()) halt.halt();
    if (!interrupted && PyErr_CheckSignals() != 0) {
      interrupted = true;
      halt.halt();
    }
  }
  {
    py::gil_scoped_release release;
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  halt.rethrow();
  return result.get();
}

/// Runs `task` on a thread of the process's call threads: an idle one, else a new one. Threads
/// stay for the next call (at most four idle; more end), so a quick call pays no thread start.
void post_call(std::function<void()> task);

/// Runs `work` (which must own all it uses) on a call thread and waits, without the GIL, until
/// it ends; Ctrl-C raises KeyboardInterrupt at once and leaves `work` to end by itself (a
/// request already sent cannot be taken back: it ends at its own timeout).
template <class F>
auto run_detached(F work) -> decltype(work()) {
  using R = decltype(work());
  auto task = std::make_shared<std::packaged_task<R()>>(std::move(work));
  std::future<R> result = task->get_future();
  post_call([task] { (*task)(); });
  {
    // A quick call (a query answered in a fraction of a millisecond) is waited for by yielding,
    // not sleeping: a sleeping caller's wake-up cost about 25 us of a 200 us round trip.
    py::gil_scoped_release release;
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(2);
    while (result.wait_for(std::chrono::seconds(0)) != std::future_status::ready &&
           std::chrono::steady_clock::now() < until) {
      std::this_thread::yield();
    }
  }
  for (;;) {
    {
      py::gil_scoped_release release;
      if (result.wait_for(std::chrono::milliseconds(20)) == std::future_status::ready) break;
    }
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }
  return result.get();
}

}  // namespace ispars::python
