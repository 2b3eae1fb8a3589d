#pragma once
// A DaemonOutbox that keeps what it was given, for the DDS layer's unit tests without a participant.

#include <mutex>
#include <string>
#include <vector>

#include "daemon_outbox.hpp"

namespace ispars::test {

/// Records every reply, status, update and retirement; safe from many threads.
class RecordingOutbox final : public server::DaemonOutbox {
 public:
  void send_reply(const msg::Reply& reply) override {
    std::lock_guard lock(mutex_);
    replies_.push_back(reply);
  }
  void publish_tour_progress(const msg::TourProgress&) override {}
  void publish_update(const msg::UpdateBatch& batch) override {
    std::lock_guard lock(mutex_);
    updates_.push_back(batch);
  }
  void retire_updates(const std::string& scene) override {
    std::lock_guard lock(mutex_);
    retired_.push_back(scene);
  }
  void publish_status(const msg::SceneStatus& status) override {
    std::lock_guard lock(mutex_);
    statuses_.push_back(status);
  }
  void publish_tasks(const std::string&, std::uint64_t, std::uint64_t,
                     const std::function<std::vector<msg::SceneTask>()>& tasks) override {
    const std::vector<msg::SceneTask> made = tasks();
    std::lock_guard lock(mutex_);
    tasks_.insert(tasks_.end(), made.begin(), made.end());
  }

  [[nodiscard]] std::vector<msg::Reply> replies() const {
    std::lock_guard lock(mutex_);
    return replies_;
  }
  [[nodiscard]] std::vector<msg::UpdateBatch> updates() const {
    std::lock_guard lock(mutex_);
    return updates_;
  }
  [[nodiscard]] std::vector<std::string> retired() const {
    std::lock_guard lock(mutex_);
    return retired_;
  }
  [[nodiscard]] std::vector<msg::SceneStatus> statuses() const {
    std::lock_guard lock(mutex_);
    return statuses_;
  }
  [[nodiscard]] std::vector<msg::SceneTask> tasks() const {
    std::lock_guard lock(mutex_);
    return tasks_;
  }

 private:
  mutable std::mutex mutex_;
  std::vector<msg::Reply> replies_;
  std::vector<msg::UpdateBatch> updates_;
  std::vector<std::string> retired_;
  std::vector<msg::SceneStatus> statuses_;
  std::vector<msg::SceneTask> tasks_;
};

}  // namespace ispars::test
