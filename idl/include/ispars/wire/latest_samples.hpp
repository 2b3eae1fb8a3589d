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
#include <iterator>
#include <map>
#include <mutex>
#include <optional>
#include <set>
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
      const bool alive = info.valid_data && info.instance_state == fdds::ALIVE_INSTANCE_STATE;
      receive(message, alive, alive ? sender_identity(info) : std::string(), info.instance_handle);
    }
  }

  /// One sample as the reader took it: alive (with its sender) or the end of its instance.
  void receive(const Message& message, bool alive, const std::string& sender,
               const eprosima::fastrtps::rtps::InstanceHandle_t& handle) {
    std::optional<Message> changed;
    const bool accepted = !alive || !accept_ || accept_(message, sender);  // outside the lock
    {
      std::lock_guard lock(mutex_);
      if (alive && accepted) {
        const std::string key = key_(message);
        keys_[handle] = key;
        latest_[key] = message;
        senders_[key] = sender;
        writers_[key].insert(sender);
        held_.erase(key);
        changed = message;
      } else if (alive) {
        const std::string key = key_(message);
        if (held_.size() < kMaxHeld || held_.count(key) > 0) held_[key] = {message, sender, handle};
      } else if (const auto it = keys_.find(handle); it != keys_.end()) {
        latest_.erase(it->second);
        senders_.erase(it->second);
        writers_.erase(it->second);
        keys_.erase(it);
      }
      ++changes_;
    }
    changed_.notify_all();
    if (changed && on_change_) on_change_(*changed);
  }

  /// A writer left (its participant stopped, or its lease expired after a crash): the instances
  /// it wrote last are gone with it. (Fast DDS 2.9 marks such instances NOT_ALIVE_NO_WRITERS
  /// without delivering a sample to say so.)
  ///
  /// A writer can also come back: when its participant's lease expired here while it was alive
  /// (a stalled machine), Fast DDS matches it again but does not deliver the samples this reader
  /// already took. Its instances are then restored as they were when it left, unless another
  /// writer has written them since.
  void on_subscription_matched(eprosima::fastdds::dds::DataReader*,
                               const eprosima::fastdds::dds::SubscriptionMatchedStatus& status) override {
    if (status.current_count_change == 0) return;
    const std::string sender = identity_of(status.last_publication_handle);
    std::vector<Message> restored;
    {
      std::lock_guard lock(mutex_);
      if (status.current_count_change > 0) {
        restored = restore_departed(sender);
      } else {
        forget_departed(sender);
      }
      ++changes_;
    }
    changed_.notify_all();
    if (on_change_) {
      for (const auto& m : restored) on_change_(m);
    }
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

  /// Whether the participant `sender` wrote `key`'s instance and has not left since: the writer
  /// of its latest sample, or an earlier one still live (one daemon's two participants while it
  /// rejoins, the old one's last announcement arriving after the new one's).
  [[nodiscard]] bool written_by(const std::string& key, const std::string& sender) const {
    std::lock_guard lock(mutex_);
    const auto it = writers_.find(key);
    return it != writers_.end() && it->second.count(sender) > 0;
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
      writers_[key].insert(h.sender);
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
  // Under mutex_: moves every instance `gone` wrote last to departed_.
  void forget_departed(const std::string& gone) {
    for (auto it = writers_.begin(); it != writers_.end();) {
      it->second.erase(gone);
      it = it->second.empty() ? writers_.erase(it) : std::next(it);
    }
    std::vector<Departed> left;
    for (auto it = senders_.begin(); it != senders_.end();) {
      if (it->second != gone) {
        ++it;
        continue;
      }
      Departed d{it->first, latest_.at(it->first), {}};
      for (auto k = keys_.begin(); k != keys_.end();) {
        if (k->second == it->first) {
          d.handle = k->first;
          k = keys_.erase(k);
        } else {
          ++k;
        }
      }
      left.push_back(std::move(d));
      latest_.erase(it->first);
      writers_.erase(it->first);  // its instance is gone: no other writer's sample of it is kept
      it = senders_.erase(it);
    }
    std::erase_if(held_, [&](const auto& entry) { return entry.second.sender == gone; });
    if (left.empty()) return;
    departed_[gone] = std::move(left);
    departed_order_.push_back(gone);
    while (departed_order_.size() > kMaxDeparted) {  // a participant that never comes back
      departed_.erase(departed_order_.front());
      departed_order_.erase(departed_order_.begin());
    }
  }

  // Under mutex_: puts back what `sender` wrote before it left, where no one wrote since.
  std::vector<Message> restore_departed(const std::string& sender) {
    std::vector<Message> restored;
    const auto it = departed_.find(sender);
    if (it == departed_.end()) return restored;
    for (Departed& d : it->second) {
      if (latest_.count(d.key) > 0) continue;
      latest_[d.key] = d.message;
      senders_[d.key] = sender;
      writers_[d.key].insert(sender);
      keys_[d.handle] = d.key;
      restored.push_back(std::move(d.message));
    }
    departed_.erase(it);
    std::erase(departed_order_, sender);
    return restored;
  }

  static constexpr std::size_t kMaxHeld = 1024;    // refused samples kept for recheck(), at most
  static constexpr std::size_t kMaxDeparted = 64;  // writers that left, kept in case they return
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
  std::map<std::string, std::set<std::string>> writers_;  // live participants that wrote each key
  std::map<std::string, Held> held_;                      // refused by accept_, latest per key
  struct Departed {
    std::string key;
    Message message;
    eprosima::fastrtps::rtps::InstanceHandle_t handle;
  };
  std::map<std::string, std::vector<Departed>> departed_;  // by the sender that left
  std::vector<std::string> departed_order_;                // oldest first
  std::uint64_t changes_ = 0;
};

}  // namespace ispars::wire
