#pragma once
// The latest sample of every live instance of a keyed, transient-local topic (scene status,
// daemon announcements), kept up to date by a reader listener.

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace ispars::wire {

/// Tracks the latest sample per instance; an instance whose writers are gone (a daemon died or
/// unregistered it) disappears. `key` names an instance (the topic's key field).
template <class Message>
class LatestSamples final : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using KeyOf = std::function<std::string(const Message&)>;
  using OnChange = std::function<void(const Message&)>;

  explicit LatestSamples(KeyOf key, OnChange on_change = {}) : key_(std::move(key)), on_change_(std::move(on_change)) {}

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    namespace fdds = eprosima::fastdds::dds;
    Message message;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
      const auto handle = info.instance_handle;
      std::optional<Message> changed;
      {
        std::lock_guard lock(mutex_);
        if (info.valid_data && info.instance_state == fdds::ALIVE_INSTANCE_STATE) {
          const std::string key = key_(message);
          keys_[handle] = key;
          latest_[key] = message;
          changed = message;
        } else if (const auto it = keys_.find(handle); it != keys_.end()) {
          latest_.erase(it->second);
          keys_.erase(it);
        }
        ++changes_;
      }
      changed_.notify_all();
      if (changed && on_change_) on_change_(*changed);
    }
  }

  /// The latest sample for `key`, if its instance is alive.
  [[nodiscard]] std::optional<Message> get(const std::string& key) const {
    std::lock_guard lock(mutex_);
    const auto it = latest_.find(key);
    if (it == latest_.end()) return std::nullopt;
    return it->second;
  }

  /// Every live instance's latest sample, by key.
  [[nodiscard]] std::vector<Message> all() const {
    std::lock_guard lock(mutex_);
    std::vector<Message> out;
    for (const auto& [key, message] : latest_) out.push_back(message);
    return out;
  }

  /// Waits until `ready` holds for the samples (checked on every change) or the timeout passes.
  template <class Predicate>
  bool wait_for(std::chrono::milliseconds timeout, Predicate ready) const {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, timeout, [&] { return ready(latest_); });
  }

 private:
  KeyOf key_;
  OnChange on_change_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::string> keys_;
  std::map<std::string, Message> latest_;
  std::uint64_t changes_ = 0;
};

}  // namespace ispars::wire
