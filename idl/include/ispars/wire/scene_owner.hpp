#pragma once
// Which daemon owns a scene: one rule that every daemon and every client computes the same way
// from the announcements DDS delivers (ispars/daemons, one live instance per running daemon).
// docs/fleet.md states it with its argument that no acknowledged commit is lost.
//
// Each daemon announces, per scene, the roadmap it can serve (msg::StoredRoadmap): its
// generation (set by the build that made it, kept by a takeover that continues it), the
// samples committed to its store and its task events. A daemon's claim on a scene is weighed by
// its key:
//
//   0. a daemon that declines the scene (its takeover failed lately, announced in `declined`)
//      is weighed below every daemon that does not;
//   1. freshness: the later generation, then the more samples (a holder counts the samples it
//      has accepted to reach, its target, since it will commit them), then the more task events
//      (inspection tasks added, plus those removed);
//   2. holding: of two equally fresh copies, the one already served;
//   3. the rendezvous weight of (scene, server_id), then the lower id: a tie breaker every
//      party computes alike.
//
// The owner is the live daemon holding or offering the scene with the highest key. A copy handed
// over to a daemon that is still live (`yielded_to`) weighs nothing. Clients address the holder
// while there is one (holder_of); a holder that is outweighed gives the scene up to the daemon
// that outweighs it (owner_of), and that daemon takes it over, continuing its own copy.

#include <compare>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ispars.h"

namespace ispars::wire {

/// How fresh a copy of a scene's roadmap is: the later generation, then the more samples, then
/// the more task events (a task added or removed is a commit of no sample). {0, 0, 0} is no copy.
struct Freshness {
  std::uint64_t generation = 0;
  std::uint64_t samples = 0;
  std::uint64_t task_events = 0;
  auto operator<=>(const Freshness&) const = default;
};

/// The rendezvous weight of (`scene`, `server_id`): a 64-bit mix of both names, the same on every
/// machine and in every release of this protocol.
[[nodiscard]] std::uint64_t rendezvous_weight(std::string_view scene, std::string_view server_id);

/// Whether daemon `a` outranks daemon `b` by weight alone for `scene` (higher weight; the lower
/// id on a tie).
[[nodiscard]] bool outranks(std::string_view scene, std::string_view a, std::string_view b);

/// Whether the announcement lists `scene` in `loaded` / `available`.
[[nodiscard]] bool holds(const msg::DaemonInfo& daemon, std::string_view scene);
[[nodiscard]] bool offers(const msg::DaemonInfo& daemon, std::string_view scene);

/// The roadmap of `scene` that `daemon` announces; nullptr when it announces none.
[[nodiscard]] const msg::StoredRoadmap* roadmap_of(const msg::DaemonInfo& daemon, std::string_view scene);

/// The freshness `daemon`'s claim on `scene` carries among `live`: its copy's generation, samples
/// (a holder's target when larger) and task events; {0, 0, 0} without a copy or when it handed
/// the copy to a daemon in `live`.
[[nodiscard]] Freshness claim_freshness(const msg::DaemonInfo& daemon, std::string_view scene,
                                        std::span<const msg::DaemonInfo> live);

/// Whether `daemon` declines `scene`: it announces that its takeover of it failed lately, and
/// does not hold it. A declining daemon is weighed below every other, so the rule names the next.
[[nodiscard]] bool declines(const msg::DaemonInfo& daemon, std::string_view scene);

/// Whether daemon `a`'s claim on `scene` outweighs `b`'s among `live` (declining, freshness,
/// holding, weight).
[[nodiscard]] bool outweighs(std::string_view scene, const msg::DaemonInfo& a, const msg::DaemonInfo& b,
                             std::span<const msg::DaemonInfo> live);

/// The live daemon holding `scene` with the highest key (the one clients address); empty when
/// none does.
[[nodiscard]] std::string holder_of(std::string_view scene, std::span<const msg::DaemonInfo> live);

/// The live daemon holding or offering `scene` with the highest key: the one that should hold it.
/// Empty when none does.
[[nodiscard]] std::string assigned_daemon(std::string_view scene, std::span<const msg::DaemonInfo> live);

/// Where a request for `scene` goes: holder_of(), else assigned_daemon().
[[nodiscard]] std::string owner_of(std::string_view scene, std::span<const msg::DaemonInfo> live);

}  // namespace ispars::wire
