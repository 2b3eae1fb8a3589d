#pragma once
// The scenes the gateway follows: one SceneFeed per scene, made when a browser first asks for it
// and dropped once no browser (nor a mesh request) has held it for a while, so that the gateway's
// memory follows what is watched, not everything ever watched.

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ispars/client/client.hpp"
#include "ispars/web/scene_feed.hpp"

namespace ispars::web {

class FeedSet {
 public:
  /// At most `max_scenes` feeds at once; a feed no one holds is dropped after `linger`.
  FeedSet(client::Client& client, DrawLimits limits, std::size_t max_scenes, std::chrono::milliseconds linger);

  /// The feed of `scene`, made on first use (blocks while the daemon is asked: call it on a
  /// worker). Throws when no daemon holds the scene, or when max_scenes feeds are held.
  std::shared_ptr<SceneFeed> get(const std::string& scene);
  /// Drops the feeds no one has held for `linger` (blocks while their replicas stop: call it
  /// on a worker). Returns the scenes dropped.
  std::vector<std::string> sweep();
  [[nodiscard]] std::size_t size() const;
  /// Drops every feed.
  void clear();

 private:
  struct Entry {
    std::shared_ptr<SceneFeed> feed;
    bool idle = false;  // held by no one at the last sweep, since `idle_since`
    std::chrono::steady_clock::time_point idle_since;
  };
  // Takes the feeds held by no one for `linger` out of the map (under the lock).
  void take_idle(std::chrono::milliseconds linger, std::vector<std::shared_ptr<SceneFeed>>& out);

  client::Client& client_;
  const DrawLimits limits_;
  const std::size_t max_scenes_;
  const std::chrono::milliseconds linger_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> feeds_;
};

}  // namespace ispars::web
