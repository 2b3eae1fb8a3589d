#pragma once
// A DaemonOutbox that keeps what it was given, for the DDS layer's unit tests without a participant.

#include <mutex>
#include <string>
#include <vector>

#include "ispars/server/daemon_outbox.hpp"

namespace ispars::test {

/// Records every reply, status, update and retirement; safe from many threads.
class RecordingOutbox final : public server::DaemonOutbox {
 public:
  void send_reply(const msg::Reply& reply) override { keep(replies_, reply); }
  void publish_tour_progress(const msg::TourProgress&) override {}
  void publish_update(const msg::UpdateBatch& batch) override { keep(updates_, batch); }
  void retire_updates(const std::string& scene) override { keep(retired_, scene); }
  void publish_status(const msg::SceneStatus& status) override { keep(statuses_, status); }
  void publish_tasks(const std::string&, std::uint64_t, std::uint64_t,
                     const std::function<std::vector<msg::SceneTask>()>& tasks) override {
    const std::vector<msg::SceneTask> made = tasks();
    std::lock_guard lock(mutex_);
    tasks_.insert(tasks_.end(), made.begin(), made.end());
  }

  [[nodiscard]] std::vector<msg::Reply> replies() const { return copy(replies_); }
  [[nodiscard]] std::vector<msg::UpdateBatch> updates() const { return copy(updates_); }
  [[nodiscard]] std::vector<std::string> retired() const { return copy(retired_); }
  [[nodiscard]] std::vector<msg::SceneStatus> statuses() const { return copy(statuses_); }
  [[nodiscard]] std::vector<msg::SceneTask> tasks() const { return copy(tasks_); }

 private:
  template <class T>
  void keep(std::vector<T>& into, const T& value) {
    std::lock_guard lock(mutex_);
    into.push_back(value);
  }
  template <class T>
  T copy(const T& recorded) const {
    std::lock_guard lock(mutex_);
    return recorded;
  }
  mutable std::mutex mutex_;
  std::vector<msg::Reply> replies_;
  std::vector<msg::UpdateBatch> updates_;
  std::vector<std::string> retired_;
  std::vector<msg::SceneStatus> statuses_;
  std::vector<msg::SceneTask> tasks_;
};

}  // namespace ispars::test
