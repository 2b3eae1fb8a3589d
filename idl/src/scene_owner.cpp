#include "ispars/wire/scene_owner.hpp"

#include <algorithm>

namespace ispars::wire {
namespace {

// FNV-1a over the bytes, then the splitmix64 finaliser: names that differ in one byte get
// unrelated weights.
std::uint64_t mix(std::uint64_t h) {
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

template <class Sequence>
bool contains(const Sequence& names, std::string_view name) {
  return std::any_of(names.begin(), names.end(), [&](const auto& n) { return n.to_string() == name; });
}

// The best of `live` for `scene` among those `eligible` accepts; empty when none.
template <class Eligible>
std::string best(std::string_view scene, std::span<const msg::DaemonInfo> live, Eligible eligible) {
  std::string winner;
  for (const msg::DaemonInfo& d : live) {
    if (!eligible(d)) continue;
    const std::string id = d.server_id().to_string();
    if (winner.empty() || outranks(scene, id, winner)) winner = id;
  }
  return winner;
}

}  // namespace

std::uint64_t rendezvous_weight(std::string_view scene, std::string_view server_id) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const auto feed = [&](std::string_view s) {
    for (const char c : s) {
      h ^= static_cast<unsigned char>(c);
      h *= 0x100000001b3ULL;
    }
  };
  feed(scene);
  h ^= 0xff;  // a separator no name contains: ("ab", "c") and ("a", "bc") differ
  h *= 0x100000001b3ULL;
  feed(server_id);
  return mix(h);
}

bool outranks(std::string_view scene, std::string_view a, std::string_view b) {
  const std::uint64_t wa = rendezvous_weight(scene, a);
  const std::uint64_t wb = rendezvous_weight(scene, b);
  return wa != wb ? wa > wb : a < b;
}

bool holds(const msg::DaemonInfo& daemon, std::string_view scene) { return contains(daemon.loaded(), scene); }
bool offers(const msg::DaemonInfo& daemon, std::string_view scene) { return contains(daemon.available(), scene); }
bool stores(const msg::DaemonInfo& daemon, std::string_view scene) { return contains(daemon.stored(), scene); }

std::string holder_of(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  return best(scene, live, [&](const msg::DaemonInfo& d) { return holds(d, scene); });
}

std::string assigned_daemon(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  std::string with_roadmap =
      best(scene, live, [&](const msg::DaemonInfo& d) { return offers(d, scene) && stores(d, scene); });
  if (!with_roadmap.empty()) return with_roadmap;
  return best(scene, live, [&](const msg::DaemonInfo& d) { return offers(d, scene); });
}

std::string owner_of(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  std::string holder = holder_of(scene, live);
  return !holder.empty() ? holder : assigned_daemon(scene, live);
}

}  // namespace ispars::wire
