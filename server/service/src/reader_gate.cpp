#include "ispars/service/reader_gate.hpp"

namespace ispars::service {

std::unique_ptr<ReaderGate::Pass> ReaderGate::enter(std::chrono::steady_clock::time_point deadline) {
  std::lock_guard lock(mutex_);
  if (holds_ > 0) throw ReaderRefused(hold_why_);
  readers_.emplace_back();
  readers_.back().deadline = deadline;
  return std::make_unique<Pass>(*this, std::prev(readers_.end()));
}

std::unique_ptr<ReaderGate::Hold> ReaderGate::hold_off(const std::string& why) {
  std::lock_guard lock(mutex_);
  ++holds_;
  hold_why_ = why;
  stop_locked(why);
  return std::make_unique<Hold>(*this);
}

void ReaderGate::stop_all(const std::string& why) {
  std::lock_guard lock(mutex_);
  stop_locked(why);
}

std::size_t ReaderGate::readers() const {
  std::lock_guard lock(mutex_);
  return readers_.size();
}

void ReaderGate::stop_locked(const std::string& why) {
  for (Reader& r : readers_) {
    if (r.stop) continue;
    r.why = why;
    r.stop = true;
  }
}

ReaderGate::Pass::~Pass() {
  std::lock_guard lock(gate_.mutex_);
  gate_.readers_.erase(at_);
}

bool ReaderGate::Pass::keep_going() const {
  return !at_->stop.load() && std::chrono::steady_clock::now() < at_->deadline;
}

std::string ReaderGate::Pass::why_stopped() const {
  std::lock_guard lock(gate_.mutex_);
  if (at_->stop) return at_->why;
  return "its time ran out";
}

ReaderGate::Hold::~Hold() {
  std::lock_guard lock(gate_.mutex_);
  --gate_.holds_;
}

}  // namespace ispars::service
