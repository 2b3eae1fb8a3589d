#pragma once
// Readers that may run long (a verify over a large roadmap) and the writers that must not wait
// for them. A writer (an unload, a drop, a job about to start, the daemon stopping) stops the
// running readers, each at its next check-in, and keeps new ones out while it works.

#include <atomic>
#include <chrono>
#include <list>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace ispars::service {

/// Thrown by ReaderGate::enter while a writer holds readers off; the message says which.
struct ReaderRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// See the file comment. Safe from any thread; must outlive its passes and holds.
class ReaderGate {
 public:
  class Pass;
  class Hold;

  /// Lets a reader in until `deadline`; throws ReaderRefused naming the writer that holds
  /// readers off.
  [[nodiscard]] std::unique_ptr<Pass> enter(std::chrono::steady_clock::time_point deadline);
  /// Stops every running reader with `why` and keeps new ones out while the hold lives.
  [[nodiscard]] std::unique_ptr<Hold> hold_off(const std::string& why);
  /// Stops every running reader with `why`; new ones may enter.
  void stop_all(const std::string& why);
  /// Readers inside now.
  [[nodiscard]] std::size_t readers() const;

 private:
  struct Reader {
    std::atomic<bool> stop{false};
    std::string why;  // under mutex_
    std::chrono::steady_clock::time_point deadline;
  };
  void stop_locked(const std::string& why);
  mutable std::mutex mutex_;
  std::list<Reader> readers_;
  int holds_ = 0;
  std::string hold_why_;
};

/// A reader inside the gate: asks keep_going() between small steps, and leaves on destruction.
class ReaderGate::Pass {
 public:
  Pass(ReaderGate& gate, std::list<Reader>::iterator at) : gate_(gate), at_(at) {}
  ~Pass();
  Pass(const Pass&) = delete;
  Pass& operator=(const Pass&) = delete;
  /// False once a writer stopped it or its deadline passed.
  [[nodiscard]] bool keep_going() const;
  /// Why it was stopped ("the budget of N s ran out" when its deadline passed).
  [[nodiscard]] std::string why_stopped() const;

 private:
  ReaderGate& gate_;
  std::list<Reader>::iterator at_;
};

/// Keeps readers out while it lives.
class ReaderGate::Hold {
 public:
  explicit Hold(ReaderGate& gate) : gate_(gate) {}
  ~Hold();
  Hold(const Hold&) = delete;
  Hold& operator=(const Hold&) = delete;

 private:
  ReaderGate& gate_;
};

}  // namespace ispars::service
