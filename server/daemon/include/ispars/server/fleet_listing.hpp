#pragma once
// What this daemon tells the fleet it has, besides the scenes it holds: the scene files in its
// scene directory and the roadmaps stored in its data directory, as last announced (the fleet's
// rule runs on what the others were told, and the directories are not rescanned on every tick);
// the scenes it handed to another daemon, announced with its copy until it holds them again; and
// a note per scene of what the fleet last decided about it here, for the scenes list.
// Safe from many threads. Knows nothing of DDS: it fills the announcement's message.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ispars.h"
#include "ispars/service/roadmap_service.hpp"

namespace ispars::server {

class FleetListing {
 public:
  FleetListing(std::filesystem::path scene_dir, std::filesystem::path data_dir);

  /// Rescans both directories; `loaded` are the scenes held here (their stores are the
  /// service's, not listed as stored), none before the service has started (no store is listed
  /// then). True when what is announced changed. A store that cannot be served is noted (and
  /// logged once per reason): one built on another version of its scene file included, and one
  /// whose damage `scrubbed` names (the service's background check of stored copies).
  bool refresh(const std::optional<std::vector<std::string>>& loaded,
               const std::function<std::string(const std::string&)>& scrubbed = {});
  /// Fills `info`'s scene files, stored scenes and roadmaps: `held` (the roadmaps held now), then
  /// the stored ones not held; a scene handed over and not held again names its winner and the
  /// samples accepted here.
  void describe(msg::DaemonInfo& info, std::vector<service::ServedRoadmap> held) const;

  /// What a daemon had accepted of a scene when it handed it over: the winner carries it.
  struct Handover {
    std::string to;                 ///< the winner
    std::uint64_t accepted = 0;     ///< samples accepted here (an extend's target)
    std::uint64_t task_events = 0;  ///< task events accepted here (a queued addition counted)
  };
  /// `scene` was handed over as `handover` says; `note` says so. Announced with the stored copy
  /// (yielded_to, its target, and its task events: the winner carries the task additions
  /// acknowledged here that the handover cancelled, from ispars/tasks).
  void hand_over(const std::string& scene, Handover handover, const std::string& note);
  /// `scene` is held here again: no longer announced as handed over, nor declined.
  void held_again(const std::string& scene);
  /// This daemon's takeover of `scene` failed: announced as declined (wire::declines) until
  /// `until`, when it is tried again, so that the rule names another daemon meanwhile.
  void decline(const std::string& scene, std::chrono::steady_clock::time_point until);

  /// The scenes handed over and not held again, each with its winner (for the metrics).
  [[nodiscard]] std::vector<std::pair<std::string, std::string>> handed_over() const;
  /// How many scenes this daemon declines now.
  [[nodiscard]] std::size_t declined_now() const;
  /// The stored copies the last refresh found it cannot serve (for the metrics).
  [[nodiscard]] std::vector<std::string> unservable() const;

  void set_note(const std::string& scene, const std::string& note);
  /// What the fleet last decided about `scene` here; empty if nothing.
  [[nodiscard]] std::string note(const std::string& scene) const;

 private:
  const std::filesystem::path scene_dir_;
  const std::filesystem::path data_dir_;
  service::SceneFingerprints
      fingerprints_;  // the scene files' as they are now: a stored copy built on another is not offered
  mutable std::mutex mutex_;
  std::vector<std::string> available_;
  std::vector<std::string> stored_;
  std::vector<service::ServedRoadmap> stored_roadmaps_;  // stored, not loaded
  std::map<std::string, Handover> handed_over_;
  std::map<std::string, std::string> notes_;
  std::map<std::string, std::string> unservable_;                          // as last listed, with why
  std::map<std::string, std::chrono::steady_clock::time_point> declined_;  // until when
};

}  // namespace ispars::server
