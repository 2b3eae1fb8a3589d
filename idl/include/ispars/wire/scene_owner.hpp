#pragma once
// Which daemon owns a scene: one rule that every daemon and every client computes the same way
// from the announcements DDS delivers (ispars/daemons, one live instance per running daemon).
//
//   1. A scene held by a live daemon (in its `loaded`) stays with it.
//   2. Otherwise it is assigned by rendezvous hashing: among the live daemons that offer it (in
//      `available`), those with a stored roadmap of it (in `stored`) first, the one whose weight
//      rendezvous_weight(scene, server_id) is highest.
//   3. Two daemons holding one scene at once (each decided before it saw the other) is settled by
//      the same weights: the lower yields (outranks()).
//
// A daemon joining moves nothing (rule 1); a daemon leaving frees exactly the scenes it held, and
// each goes to the one daemon rule 2 names.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "ispars.h"

namespace ispars::wire {

/// The rendezvous weight of (`scene`, `server_id`): a 64-bit mix of both names, the same on every
/// machine and in every release of this protocol.
[[nodiscard]] std::uint64_t rendezvous_weight(std::string_view scene, std::string_view server_id);

/// Whether daemon `a` outranks daemon `b` for `scene` (higher weight; the lower id on a tie).
[[nodiscard]] bool outranks(std::string_view scene, std::string_view a, std::string_view b);

/// Whether the announcement lists `scene` in `loaded` / `available` / `stored`.
[[nodiscard]] bool holds(const msg::DaemonInfo& daemon, std::string_view scene);
[[nodiscard]] bool offers(const msg::DaemonInfo& daemon, std::string_view scene);
[[nodiscard]] bool stores(const msg::DaemonInfo& daemon, std::string_view scene);

/// The live daemon holding `scene` (the highest ranked if several do); empty when none does.
[[nodiscard]] std::string holder_of(std::string_view scene, std::span<const msg::DaemonInfo> live);

/// The daemon rule 2 assigns `scene` to among `live`, ignoring holders; empty when none offers it.
[[nodiscard]] std::string assigned_daemon(std::string_view scene, std::span<const msg::DaemonInfo> live);

/// The owner: holder_of(), else assigned_daemon().
[[nodiscard]] std::string owner_of(std::string_view scene, std::span<const msg::DaemonInfo> live);

}  // namespace ispars::wire
