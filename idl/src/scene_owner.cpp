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

}  // namespace

bool outweighs(std::string_view scene, const msg::DaemonInfo& a, const msg::DaemonInfo& b,
               std::span<const msg::DaemonInfo> live);

namespace {

// The daemon of `live` with the highest key for `scene` among those `eligible` accepts; empty
// when none.
template <class Eligible>
std::string best(std::string_view scene, std::span<const msg::DaemonInfo> live, Eligible eligible) {
  const msg::DaemonInfo* winner = nullptr;
  for (const msg::DaemonInfo& d : live) {
    if (!eligible(d)) continue;
    if (winner == nullptr || outweighs(scene, d, *winner, live)) winner = &d;
  }
  return winner == nullptr ? std::string() : winner->server_id().to_string();
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

const msg::StoredRoadmap* roadmap_of(const msg::DaemonInfo& daemon, std::string_view scene) {
  for (const msg::StoredRoadmap& r : daemon.roadmaps()) {
    if (r.scene().to_string() == scene) return &r;
  }
  return nullptr;
}

Freshness claim_freshness(const msg::DaemonInfo& daemon, std::string_view scene,
                          std::span<const msg::DaemonInfo> live) {
  const msg::StoredRoadmap* r = roadmap_of(daemon, scene);
  if (r == nullptr) return {};
  const std::string to = r->yielded_to().to_string();
  if (!to.empty() && to != daemon.server_id().to_string() &&
      std::any_of(live.begin(), live.end(),
                  [&](const msg::DaemonInfo& d) { return d.server_id().to_string() == to; })) {
    return {};  // handed over to a daemon that still lives: that one carries it now
  }
  const bool held = holds(daemon, scene);
  return {r->generation(), held ? std::max(r->samples(), r->target()) : r->samples(), r->task_events()};
}

bool declines(const msg::DaemonInfo& daemon, std::string_view scene) {
  return contains(daemon.declined(), scene) && !holds(daemon, scene);
}

bool outweighs(std::string_view scene, const msg::DaemonInfo& a, const msg::DaemonInfo& b,
               std::span<const msg::DaemonInfo> live) {
  const bool da = declines(a, scene);
  const bool db = declines(b, scene);
  if (da != db) return db;
  const Freshness fa = claim_freshness(a, scene, live);
  const Freshness fb = claim_freshness(b, scene, live);
  if (fa != fb) return fa > fb;
  const bool ha = holds(a, scene);
  const bool hb = holds(b, scene);
  if (ha != hb) return ha;
  return outranks(scene, a.server_id().to_string(), b.server_id().to_string());
}

std::string holder_of(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  return best(scene, live, [&](const msg::DaemonInfo& d) { return holds(d, scene); });
}

std::string assigned_daemon(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  return best(scene, live, [&](const msg::DaemonInfo& d) { return holds(d, scene) || offers(d, scene); });
}

std::string owner_of(std::string_view scene, std::span<const msg::DaemonInfo> live) {
  std::string holder = holder_of(scene, live);
  return !holder.empty() ? holder : assigned_daemon(scene, live);
}

}  // namespace ispars::wire
