#pragma once
// The latest sample of every live instance of a keyed, transient-local topic (scene status,
// daemon announcements), kept up to date by a reader listener, with who wrote it (the writer's
// participant as the transport says) and an optional rule of whose samples to accept.

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

#include "ispars/wire/identity.hpp"

namespace ispars::wire {

/// Tracks the latest sample per instance; an instance whose writers are gone (a daemon died or
/// unregistered it) disappears. `key` names an instance (the topic's key field).
template <class Message>
class LatestSamples final : public eprosima::fastdds::dds::DataReaderListener {
 public:
  using KeyOf = std::function<std::string(const Message&)>;
  using OnChange = std::function<void(const Message&)>;
  /// Whether a sample written by the participant `sender` (wire::identity_of) is accepted now.
  /// A refused sample is held (the latest per key) and tried again by recheck().
  using Accept = std::function<bool(const Message&, const std::string& sender)>;

  explicit LatestSamples(KeyOf key, OnChange on_change = {}, Accept accept = {})
      : key_(std::move(key)), on_change_(std::move(on_change)), accept_(std::move(accept)) {}

  void on_data_available(eprosima::fastdds::dds::DataReader* reader) override {
    namespace fdds = eprosima::fastdds::dds;
    Message message;
    fdds::SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK) {
      const auto handle = info.instance_handle;
      std::optional<Message> changed;
      const bool alive = info.valid_data && info.instance_state == fdds::ALIVE_INSTANCE_STATE;
      const std::string sender = alive ? sender_identity(info) : std::string();
      const bool accepted = !alive || !accept_ || accept_(message, sender);  // outside the lock
      {
        std::lock_guard lock(mutex_);
        if (alive && accepted) {
          const std::string key = key_(message);
          keys_[handle] = key;
          latest_[key] = message;
          senders_[key] = sender;
          held_.erase(key);
          changed = message;
        } else if (alive) {
          const std::string key = key_(message);
          if (held_.size() < kMaxHeld || held_.count(key) > 0) held_[key] = {message, sender, handle};
        } else if (const auto it = keys_.find(handle); it != keys_.end()) {
          latest_.erase(it->second);
          senders_.erase(it->second);
          keys_.erase(it);
        }
        ++changes_;
      }
      changed_.notify_all();
      if (changed && on_change_) on_change_(*changed);
    }
  }

  /// A writer left (its participant stopped, or its lease expired after a crash): the instances
  /// it wrote last are gone with it. (Fast DDS 2.9 marks such instances NOT_ALIVE_NO_WRITERS
  /// without delivering a sample to say so.)
  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override {
    if (status.current_count_change >= 0) return;
    const std::string gone = identity_of(status.last_publication_handle);
    {
      std::lock_guard lock(mutex_);
      for (auto it = senders_.begin(); it != senders_.end();) {
        if (it->second != gone) {
          ++it;
          continue;
        }
        latest_.erase(it->first);
        std::erase_if(keys_, [&](const auto& entry) { return entry.second == it->first; });
        it = senders_.erase(it);
      }
      std::erase_if(held_, [&](const auto& entry) { return entry.second.sender == gone; });
      ++changes_;
    }
    changed_.notify_all();
  }

  /// The latest sample for `key`, if its instance is alive.
  [[nodiscard]] std::optional<Message> get(const std::string& key) const {
    std::lock_guard lock(mutex_);
    const auto it = latest_.find(key);
    if (it == latest_.end()) return std::nullopt;
    return it->second;
  }

  /// The participant (wire::identity_of) that wrote the latest sample for `key`; empty if none.
  [[nodiscard]] std::string sender(const std::string& key) const {
    std::lock_guard lock(mutex_);
    const auto it = senders_.find(key);
    return it == senders_.end() ? std::string() : it->second;
  }

  /// Tries the held (refused) samples again, after what the accept rule depends on changed.
  void recheck() {
    std::map<std::string, Held> held;
    {
      std::lock_guard lock(mutex_);
      held = held_;
    }
    std::vector<Message> changed;
    for (const auto& [key, h] : held) {
      if (!accept_(h.message, h.sender)) continue;
      std::lock_guard lock(mutex_);
      const auto it = held_.find(key);
      if (it == held_.end() || it->second.sender != h.sender) continue;  // replaced meanwhile
      keys_[h.handle] = key;
      latest_[key] = h.message;
      senders_[key] = h.sender;
      held_.erase(it);
      changed.push_back(h.message);
    }
    if (changed.empty()) return;
    changed_.notify_all();
    if (on_change_) {
      for (const auto& m : changed) on_change_(m);
    }
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
  static constexpr std::size_t kMaxHeld = 1024;  // refused samples kept for recheck(), at most
  struct Held {
    Message message;
    std::string sender;
    eprosima::fastrtps::rtps::InstanceHandle_t handle;
  };
  KeyOf key_;
  OnChange on_change_;
  Accept accept_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::map<eprosima::fastrtps::rtps::InstanceHandle_t, std::string> keys_;
  std::map<std::string, Message> latest_;
  std::map<std::string, std::string> senders_;
  std::map<std::string, Held> held_;  // refused by accept_, latest per key
  std::uint64_t changes_ = 0;
};

}  // namespace ispars::wire
