#include "ispars/web/feed_set.hpp"

#include <fmt/format.h>

namespace ispars::web {

FeedSet::FeedSet(client::Client& client, DrawLimits limits, std::size_t max_scenes, std::chrono::milliseconds linger)
    : client_(client), limits_(limits), max_scenes_(max_scenes), linger_(linger) {}

std::shared_ptr<SceneFeed> FeedSet::get(const std::string& scene) {
  std::vector<std::shared_ptr<SceneFeed>> dropped;  // destroyed after the lock: their replicas stop
  {
    std::lock_guard lock(mutex_);
    if (auto it = feeds_.find(scene); it != feeds_.end()) {
      it->second.idle = false;
      return it->second.feed;
    }
    // Full: a scene no one watches makes room at once.
    if (feeds_.size() >= max_scenes_) take_idle(std::chrono::milliseconds(0), dropped);
    if (feeds_.size() >= max_scenes_) {
      throw std::runtime_error(fmt::format("the viewer follows {} scenes already (its limit)", feeds_.size()));
    }
  }
  dropped.clear();
  auto feed = std::make_shared<SceneFeed>(client_, scene, limits_);  // outside the lock: it waits
  std::lock_guard lock(mutex_);
  auto& entry = feeds_[scene];
  if (!entry.feed) entry.feed = std::move(feed);  // a feed made meanwhile wins
  entry.idle = false;
  return entry.feed;
}

void FeedSet::take_idle(std::chrono::milliseconds linger, std::vector<std::shared_ptr<SceneFeed>>& out) {
  const auto now = std::chrono::steady_clock::now();
  for (auto it = feeds_.begin(); it != feeds_.end();) {
    // Held only here: no session or request holds it, and none can take it without the lock.
    Entry& e = it->second;
    if (e.feed.use_count() > 1) {
      e.idle = false;
    } else if (!e.idle) {
      e.idle = true;
      e.idle_since = now;
    }
    if (e.idle && now - e.idle_since >= linger) {
      out.push_back(std::move(e.feed));
      it = feeds_.erase(it);
    } else {
      ++it;
    }
  }
}

std::vector<std::string> FeedSet::sweep() {
  std::vector<std::shared_ptr<SceneFeed>> dropped;
  {
    std::lock_guard lock(mutex_);
    take_idle(linger_, dropped);
  }
  std::vector<std::string> scenes;
  for (const auto& feed : dropped) scenes.push_back(feed->scene());
  return scenes;  // `dropped` goes here, outside the lock
}

std::size_t FeedSet::size() const {
  std::lock_guard lock(mutex_);
  return feeds_.size();
}

void FeedSet::clear() {
  std::map<std::string, Entry> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(feeds_);
  }
}

}  // namespace ispars::web
