#include "ispars/server/scene_claims.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/wire/scene_owner.hpp"

namespace ispars::server {
namespace {

constexpr const char* kRequest = "request";

bool alive(const std::vector<msg::DaemonInfo>& live, const std::string& id) {
  return std::any_of(live.begin(), live.end(), [&](const msg::DaemonInfo& d) { return d.server_id() == id; });
}

// Whether a daemon among `everyone` holds `scene` with a copy at least as fresh as
// (generation, samples): the former owner's work is served again.
bool served_again(const std::string& scene, std::uint64_t generation, std::uint64_t samples,
                  const std::vector<msg::DaemonInfo>& everyone) {
  return std::any_of(everyone.begin(), everyone.end(), [&](const msg::DaemonInfo& d) {
    if (!wire::holds(d, scene)) return false;
    if (generation == 0 && samples == 0) return true;  // the former owner held no roadmap
    const msg::StoredRoadmap* r = wire::roadmap_of(d, scene);
    return r && std::pair(r->generation(), r->samples()) >= std::pair(generation, samples);
  });
}

}  // namespace

SceneClaims::SceneClaims(std::string self_id, Fleet fleet) : self_(std::move(self_id)), fleet_(std::move(fleet)) {}

void SceneClaims::claim(const std::string& scene) {
  {
    std::lock_guard lock(mutex_);
    if (claimed_.count(scene)) return;
  }
  std::vector<msg::DaemonInfo> others = fleet_.others();
  {
    // Remembered now, not only on the fleet thread's next look: a holder that leaves right after
    // refusing this claim (a daemon starting beside it) is then taken over.
    std::lock_guard lock(mutex_);
    remember_holders(others, &others);
  }
  if (const std::string holder = wire::holder_of(scene, others); !holder.empty()) {
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' is owned by daemon {}", scene, holder));
  }
  std::vector<msg::DaemonInfo> everyone = others;
  everyone.push_back(fleet_.self());
  if (const std::string assigned = wire::assigned_daemon(scene, everyone); assigned != self_) {
    const auto it = std::find_if(everyone.begin(), everyone.end(),
                                 [&](const msg::DaemonInfo& d) { return d.server_id() == assigned; });
    const wire::Freshness f = wire::claim_freshness(*it, scene, everyone);
    const wire::Freshness mine = wire::claim_freshness(everyone.back(), scene, everyone);
    const std::string why =
        f.generation == 0 ? std::string("no daemon has a copy, and its rendezvous weight is the highest")
        : f == mine       ? fmt::format(
                                "equally fresh copies are here and there (generation {}, {} samples): settled "
                                      "by rendezvous weight",
                                f.generation, f.samples)
                    : fmt::format("it has the freshest copy: generation {}, {} samples", f.generation, f.samples);
    throw params::InputError(
        kRequest, "scene",
        fmt::format("scene '{}' belongs to daemon {} by the fleet's rule ({}); load it there (ispars "
                    "does by itself)",
                    scene, assigned, why));
  }
  {
    std::lock_guard lock(mutex_);
    claimed_.insert(scene);
  }
  fleet_.announce();
  fleet_.sleep(kClaimWindow);
  const msg::DaemonInfo me = fleet_.self();
  std::vector<msg::DaemonInfo> now = fleet_.others();
  now.push_back(me);
  for (const msg::DaemonInfo& d : now) {
    const std::string id = d.server_id().to_string();
    if (id != self_ && wire::holds(d, scene) && wire::outweighs(scene, d, me, now)) {
      release(scene);
      fleet_.announce();
      throw params::InputError(
          kRequest, "scene",
          fmt::format("daemon {} claimed scene '{}' at the same moment and outranks this one: the scene "
                      "is owned by daemon {}",
                      id, scene, id));
    }
  }
}

void SceneClaims::release(const std::string& scene) {
  std::lock_guard lock(mutex_);
  claimed_.erase(scene);
}

std::vector<std::string> SceneClaims::claimed() const {
  std::lock_guard lock(mutex_);
  return {claimed_.begin(), claimed_.end()};
}

std::vector<ContestedScene> SceneClaims::contested() const {
  std::vector<msg::DaemonInfo> everyone = fleet_.others();
  everyone.push_back(fleet_.self());
  std::vector<ContestedScene> out;
  for (const std::string& scene : claimed()) {
    const std::string winner = wire::assigned_daemon(scene, everyone);
    if (winner.empty() || winner == self_) continue;
    const auto it = std::find_if(everyone.begin(), everyone.end(),
                                 [&](const msg::DaemonInfo& d) { return d.server_id() == winner; });
    const wire::Freshness theirs = wire::claim_freshness(*it, scene, everyone);
    const wire::Freshness mine = wire::claim_freshness(everyone.back(), scene, everyone);
    const bool holds = wire::holds(*it, scene);
    std::string why =
        theirs == mine
            ? fmt::format("{} equally fresh copies (generation {}, {} samples): settled by rendezvous weight",
                          holds ? "both hold" : "it has", mine.generation, mine.samples)
            : fmt::format("its copy is fresher (generation {}, {} samples; here generation {}, {} samples)",
                          theirs.generation, theirs.samples, mine.generation, mine.samples);
    out.push_back({scene, winner, holds, std::move(why)});
  }
  return out;
}

void SceneClaims::remember_holders(const std::vector<msg::DaemonInfo>& announcements,
                                   const std::vector<msg::DaemonInfo>* live) {
  for (const msg::DaemonInfo& d : announcements) {
    note_run(d);
    for (const auto& name : d.loaded()) {
      const std::string scene = name.to_string();
      const auto seen = held_by_.find(scene);
      if (seen == held_by_.end() && held_by_.size() >= kMaxRemembered) continue;
      if (seen != held_by_.end() && seen->second.id != d.server_id().to_string()) {
        // Another holder now: if the one before left the domain holding it, it is an orphan
        // until a copy as fresh as its own is served (unknown on one announcement: kept).
        if (!live) continue;
        if (!alive(*live, seen->second.id)) orphan_of(scene, seen->second);
      }
      Holder h{d.server_id().to_string()};
      if (const msg::StoredRoadmap* r = wire::roadmap_of(d, scene)) {
        h = {h.id, r->generation(), r->samples(), std::max(r->samples(), r->target())};
      }
      held_by_[scene] = std::move(h);
    }
  }
}

void SceneClaims::orphan_of(const std::string& scene, const Holder& holder) {
  if (takeovers_.size() >= kMaxRemembered && !takeovers_.count(scene)) return;
  PendingTakeover pending;
  pending.orphan = {scene, holder.id, false, std::nullopt, holder.accepted, holder.generation};
  pending.samples = holder.samples;
  if (const auto s = last_status_.find({scene, holder.id}); s != last_status_.end()) {
    pending.orphan.last_status = s->second;
  }
  takeovers_[scene] = std::move(pending);
}

void SceneClaims::add_handovers(const std::vector<msg::DaemonInfo>& others, const msg::DaemonInfo& me,
                                std::vector<OrphanScene>& out) {
  const auto now = fleet_.now();
  for (const msg::DaemonInfo& d : others) {
    for (const msg::StoredRoadmap& r : d.roadmaps()) {
      const std::string scene = r.scene().to_string();
      if (r.yielded_to().to_string() != self_ || wire::holds(d, scene)) continue;
      const std::uint64_t accepted = std::max(r.samples(), r.target());
      if (claimed_.count(scene)) {
        // Held here already: only work it accepted beyond what this daemon holds or will reach.
        const msg::StoredRoadmap* mine = wire::roadmap_of(me, scene);
        if (!mine || mine->generation() != r.generation() || std::max(mine->samples(), mine->target()) >= accepted) {
          continue;
        }
      } else if (!wire::holder_of(scene, others).empty()) {
        continue;  // another daemon took it
      }
      const auto last = handover_reported_.find(scene);
      if (last != handover_reported_.end() && now - last->second < kRetryPeriod) continue;
      if (handover_reported_.size() >= kMaxRemembered && last == handover_reported_.end()) continue;
      handover_reported_[scene] = now;
      OrphanScene orphan{scene, d.server_id().to_string(), true, std::nullopt, accepted, r.generation()};
      if (const auto s = last_status_.find({scene, orphan.former_owner}); s != last_status_.end()) {
        orphan.last_status = s->second;
      }
      out.push_back(std::move(orphan));
    }
  }
}

void SceneClaims::report_takeovers(const std::vector<msg::DaemonInfo>& others,
                                   const std::vector<msg::DaemonInfo>& everyone, std::vector<OrphanScene>& out) {
  const auto now = fleet_.now();
  for (auto it = takeovers_.begin(); it != takeovers_.end();) {
    auto& [scene, pending] = *it;
    if (fleet_.taking_over(scene)) {
      ++it;  // its end decides: claimed (erased on the next pass) or failed (reported again)
      continue;
    }
    if (claimed_.count(scene) || served_again(scene, pending.orphan.accepted_generation, pending.samples, everyone)) {
      it = takeovers_.erase(it);  // taken over here, or served
      continue;
    }
    const bool mine = wire::holder_of(scene, others).empty() && wire::assigned_daemon(scene, everyone) == self_;
    if (mine && (!pending.reported || now - *pending.reported >= retry_delay(pending.attempts))) {
      if (pending.reported) ++pending.attempts;  // the takeover failed here: once more
      pending.reported = now;
      out.push_back(pending.orphan);
    }
    ++it;
  }
}

std::vector<OrphanScene> SceneClaims::orphans() {
  const std::vector<msg::DaemonInfo> others = fleet_.others();
  std::vector<msg::DaemonInfo> everyone = others;
  everyone.push_back(fleet_.self());
  std::vector<OrphanScene> out;
  std::lock_guard lock(mutex_);
  remember_holders(others, &others);
  for (auto it = held_by_.begin(); it != held_by_.end();) {
    const auto& [scene, holder] = *it;
    const std::string now_held = wire::holder_of(scene, others);
    if (now_held == holder.id) {
      ++it;  // still held by the daemon last seen holding it
    } else if (!now_held.empty() || claimed_.count(scene)) {
      it = held_by_.erase(it);  // moved to another daemon, or here
    } else if (const auto d = std::find_if(others.begin(), others.end(),
                                           [&](const msg::DaemonInfo& o) { return o.server_id() == holder.id; });
               d != others.end()) {
      // Released while alive: on purpose (handed over: below), unless it declines the scene,
      // its takeover having failed; then whichever daemon left before is still to be taken over.
      if (!wire::declines(*d, scene)) takeovers_.erase(scene);
      it = held_by_.erase(it);
    } else {
      orphan_of(scene, holder);  // left the domain while holding it
      it = held_by_.erase(it);
    }
  }
  report_takeovers(others, everyone, out);
  add_handovers(others, everyone.back(), out);
  return out;
}

std::chrono::seconds SceneClaims::takeover_retry_in(const std::string& scene) const {
  std::lock_guard lock(mutex_);
  const auto it = takeovers_.find(scene);
  return it == takeovers_.end() || !it->second.reported ? std::chrono::seconds(0) : retry_delay(it->second.attempts);
}

void SceneClaims::observe(const msg::DaemonInfo& announcement) {
  if (announcement.server_id() == self_) return;
  std::lock_guard lock(mutex_);
  remember_holders({announcement}, nullptr);
}

void SceneClaims::note_run(const msg::DaemonInfo& announcement) {
  const std::string id = announcement.server_id().to_string();
  const auto run = runs_.find(id);
  if (run != runs_.end() && run->second == announcement.joined_ms()) return;
  if (run == runs_.end() && runs_.size() >= kMaxRemembered) return;
  if (run != runs_.end()) {
    std::erase_if(last_status_, [&](const auto& entry) { return entry.first.second == id; });
  }
  runs_[id] = announcement.joined_ms();
}

void SceneClaims::observe(const msg::SceneStatus& status) {
  // An UNLOADED status (also sent by a daemon stopping) says nothing of the roadmap it held.
  if (status.server_id() == self_ || status.state() == msg::SCENE_UNLOADED) return;
  std::lock_guard lock(mutex_);
  const std::pair key(status.scene().to_string(), status.server_id().to_string());
  const auto kept = last_status_.find(key);
  if (kept != last_status_.end()) {
    if (kept->second.status_seq() < status.status_seq()) kept->second = status;  // else a late, older one
  } else if (last_status_.size() < kMaxRemembered) {
    last_status_.emplace(key, status);
  }
}

}  // namespace ispars::server
