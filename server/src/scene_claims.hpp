#pragma once
// This daemon's claims on scenes under the fleet's ownership rule (ispars/wire/scene_owner.hpp).
// A scene is loaded only once it is claimed: no live daemon holds it, the rule assigns it to this
// daemon, the claim has been announced, and after a claim window no daemon that outranks this
// one claimed it too. Claims made at the same instant on stale views are settled afterwards by
// contested(): the outranked daemon gives the scene up. When a holder leaves the domain, the
// daemon the rule now names takes each of its scenes over (orphans()), with the last status its
// holder published, which carries the recipe.
//
// Knows nothing of DDS: the announcements and statuses it reasons about come in through Fleet.

#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "ispars.h"

namespace ispars::server {

/// What SceneClaims needs from the transport.
struct Fleet {
  /// The latest announcement of every other live daemon.
  std::function<std::vector<msg::DaemonInfo>()> others;
  /// This daemon's announcement as it would be made now (its claims included).
  std::function<msg::DaemonInfo()> self;
  /// Announces this daemon's claims to the domain.
  std::function<void()> announce;
};

/// A scene whose holder left the domain, now this daemon's to take over.
struct OrphanScene {
  std::string scene;
  std::string former_owner;
  /// The last status the former owner published while holding it (its recipe and size), if any.
  std::optional<msg::SceneStatus> last_status;
};

class SceneClaims {
 public:
  /// How long a claim waits for a concurrent one to show before loading. An announcement between
  /// two discovered daemons arrives in milliseconds on one host; this leaves a wide margin.
  static constexpr std::chrono::milliseconds kClaimWindow{300};
  /// Former holders and last statuses remembered, at most (scene names are bounded anyway).
  static constexpr std::size_t kMaxRemembered = 4096;

  SceneClaims(std::string self_id, Fleet fleet);

  /// Claims `scene` for this daemon, or throws InputError naming the daemon it belongs to. Waits
  /// the claim window. Claiming a scene already claimed here returns at once.
  void claim(const std::string& scene);
  /// Withdraws the claim (idempotent; the caller announces).
  void release(const std::string& scene);
  /// Scenes claimed here, sorted.
  [[nodiscard]] std::vector<std::string> claimed() const;

  /// Scenes claimed here that a live daemon outranking this one holds too: to give up.
  [[nodiscard]] std::vector<std::string> contested() const;
  /// Scenes whose holder left and that the rule now assigns to this daemon; each is reported once.
  [[nodiscard]] std::vector<OrphanScene> orphans();
  /// Remembers a status another daemon published (the recipe a takeover rebuilds from).
  void observe(const msg::SceneStatus& status);

 private:
  const std::string self_;
  const Fleet fleet_;
  mutable std::mutex mutex_;
  std::set<std::string> claimed_;
  std::map<std::string, std::string> held_by_;                // scene -> the other daemon last seen holding it
  std::map<std::string, msg::SceneStatus> last_status_;  // scene -> its holder's last status but UNLOADED
};

}  // namespace ispars::server
