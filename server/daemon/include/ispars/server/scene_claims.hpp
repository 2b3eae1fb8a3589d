#pragma once
// This daemon's claims on scenes under the fleet's ownership rule (ispars/wire/scene_owner.hpp,
// docs/fleet.md). A scene is loaded only once it is claimed: no live daemon holds it, the rule
// assigns it to this daemon, the claim has been announced, and after a claim window no daemon
// that outweighs this one claimed it too. A held scene that another live daemon outweighs (a
// fresher copy, or a claim made at the same instant on a stale view) is given up to it
// (contested()). A scene comes here (orphans()) when its holder left the domain and the rule now
// names this daemon, or when its holder handed it to this daemon; with the last status its
// holder published, which carries the recipe, and the samples it had accepted to reach.
//
// Knows nothing of DDS: the announcements and statuses it reasons about come in through Fleet.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <utility>
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
  /// The clock the claim window and the retry periods run on: the steady clock, unless a test
  /// gives a fake one.
  std::function<std::chrono::steady_clock::time_point()> now = [] { return std::chrono::steady_clock::now(); };
  std::function<void(std::chrono::milliseconds)> sleep = [](std::chrono::milliseconds d) {
    std::this_thread::sleep_for(d);
  };
  /// Whether a takeover of the scene that orphans() reported still runs here (beside the fleet
  /// thread): its scene stays pending while claimed, so that a failure is tried again.
  std::function<bool(const std::string& scene)> taking_over = [](const std::string&) { return false; };
};

/// A scene whose holder left the domain or handed it here, now this daemon's to take over.
struct OrphanScene {
  std::string scene;
  std::string former_owner;
  bool handed_over = false;  ///< The former owner lives and gave the scene to this daemon.
  /// The last status the former owner published while holding it (its recipe and size), if any.
  std::optional<msg::SceneStatus> last_status;
  /// The samples the former owner had accepted to reach (its announced target), 0 if unknown,
  /// and the generation of the copy it announced them for.
  std::uint64_t accepted = 0;
  std::uint64_t accepted_generation = 0;
};

/// A scene held here that another live daemon outweighs: to be given up to `winner`.
struct ContestedScene {
  std::string scene;
  std::string winner;
  bool winner_holds = false;  ///< Both hold it (claims on stale views, a partition healed).
  std::string why;            ///< Why the winner outweighs this daemon, in words for the log.
};

class SceneClaims {
 public:
  /// How long a claim waits for a concurrent one to show before loading. An announcement between
  /// two discovered daemons arrives in milliseconds on one host; this leaves a wide margin.
  static constexpr std::chrono::milliseconds kClaimWindow{300};
  /// Former holders and last statuses remembered, at most (scene names are bounded anyway).
  static constexpr std::size_t kMaxRemembered = 4096;
  /// How long a scene to take over that is still not held waits before it is reported again
  /// the first time; each later time twice as long, up to 16 times (80 s).
  static constexpr std::chrono::seconds kRetryPeriod{5};
  [[nodiscard]] static std::chrono::seconds retry_delay(unsigned attempts) {
    return kRetryPeriod * (1u << std::min(attempts, 4u));
  }

  SceneClaims(std::string self_id, Fleet fleet);

  /// Claims `scene` for this daemon, or throws InputError naming the daemon it belongs to. Waits
  /// the claim window. Claiming a scene already claimed here returns at once.
  void claim(const std::string& scene);
  /// Withdraws the claim (idempotent; the caller announces).
  void release(const std::string& scene);
  /// Scenes claimed here, sorted.
  [[nodiscard]] std::vector<std::string> claimed() const;

  /// Scenes claimed here that another live daemon outweighs: to give up to it.
  [[nodiscard]] std::vector<ContestedScene> contested() const;
  /// Scenes whose holder left and that the rule now assigns to this daemon, and scenes a live
  /// holder handed to this daemon; each reported again after retry_delay while nobody holds it
  /// and the rule still names this daemon (a takeover that failed is tried again). A scene whose
  /// holder left is remembered until some daemon serves a copy at least as fresh as the former
  /// owner's, so a takeover that fails elsewhere (that daemon declines the scene) comes here
  /// with the former owner's recipe when the rule names this daemon next.
  [[nodiscard]] std::vector<OrphanScene> orphans();
  /// How long until a takeover of `scene` that failed now is tried again (0: none pending).
  [[nodiscard]] std::chrono::seconds takeover_retry_in(const std::string& scene) const;
  /// Remembers a status another daemon published (the recipe a takeover rebuilds from): per
  /// scene and daemon, the one with the highest status_seq of the daemon's run (its announced
  /// joined_ms). DDS orders samples per writer only: while a daemon rejoins, a late status of its
  /// old participant can arrive after a newer one of its new participant, and is ignored.
  void observe(const msg::SceneStatus& status);
  /// Another daemon's announcement as it arrives: the scenes it holds are remembered at once, so
  /// a holder that leaves before the next pass of the fleet thread is still taken over.
  void observe(const msg::DaemonInfo& announcement);

 private:
  /// The other daemon last seen holding a scene, and the copy it announced.
  struct Holder {
    std::string id;
    std::uint64_t generation = 0, samples = 0;  // its committed copy
    std::uint64_t accepted = 0;                 // what it announced accepting to reach
  };
  /// A scene whose holder left the domain while holding it, remembered by every daemon until a
  /// daemon serves a copy at least as fresh (a third daemon's takeover that fails and releases
  /// the scene leaves it here, so the next daemon the rule names takes it over).
  struct PendingTakeover {
    OrphanScene orphan;         // its accepted_generation is the former owner's copy's
    std::uint64_t samples = 0;  // the former owner's committed samples
    std::optional<std::chrono::steady_clock::time_point> reported;  // here, last time
    unsigned attempts = 0;                                          // reported again so far
  };

  const std::string self_;
  const Fleet fleet_;
  mutable std::mutex mutex_;
  std::set<std::string> claimed_;
  std::map<std::string, Holder> held_by_;  // scene -> the other daemon last seen holding it
  std::map<std::string, std::chrono::steady_clock::time_point> handover_reported_;
  std::map<std::string, PendingTakeover> takeovers_;  // scenes whose holder left, not yet served again
  // (scene, daemon) -> that daemon's last status of the scene but UNLOADED: another daemon's
  // status never hides the former owner's recipe.
  std::map<std::pair<std::string, std::string>, msg::SceneStatus> last_status_;
  // daemon -> the joined_ms of its run last announced: a new run's status_seq starts again.
  std::map<std::string, std::uint64_t> runs_;

  // With mutex_ held: notes the run `announcement` belongs to; a new run's daemon has its older
  // run's statuses forgotten (their status_seq do not compare with the new run's).
  void note_run(const msg::DaemonInfo& announcement);
  // All with mutex_ held.
  void remember_holders(const std::vector<msg::DaemonInfo>& announcements, const std::vector<msg::DaemonInfo>* live);
  void orphan_of(const std::string& scene, const Holder& holder);
  void add_handovers(const std::vector<msg::DaemonInfo>& others, const msg::DaemonInfo& me,
                     std::vector<OrphanScene>& out);
  void report_takeovers(const std::vector<msg::DaemonInfo>& others, const std::vector<msg::DaemonInfo>& everyone,
                        std::vector<OrphanScene>& out);
};

}  // namespace ispars::server
