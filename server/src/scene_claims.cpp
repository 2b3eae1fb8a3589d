#include "scene_claims.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <thread>

#include "ispars/input_error.hpp"
#include "ispars/wire/scene_owner.hpp"

namespace ispars::server {
namespace {

constexpr const char* kRequest = "request";

bool alive(const std::vector<msg::DaemonInfo>& live, const std::string& id) {
  return std::any_of(live.begin(), live.end(), [&](const msg::DaemonInfo& d) { return d.server_id() == id; });
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
    remember_holders(others);
  }
  if (const std::string holder = wire::holder_of(scene, others); !holder.empty()) {
    throw InputError(kRequest, "scene", fmt::format("scene '{}' is owned by daemon {}", scene, holder));
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
        : f == mine       ? fmt::format("equally fresh copies are here and there (generation {}, {} samples): settled "
                                        "by rendezvous weight",
                                        f.generation, f.samples)
                          : fmt::format("it has the freshest copy: generation {}, {} samples", f.generation, f.samples);
    throw InputError(kRequest, "scene",
                     fmt::format("scene '{}' belongs to daemon {} by the fleet's rule ({}); load it there (ispars "
                                 "does by itself)",
                                 scene, assigned, why));
  }
  {
    std::lock_guard lock(mutex_);
    claimed_.insert(scene);
  }
  fleet_.announce();
  std::this_thread::sleep_for(kClaimWindow);
  const msg::DaemonInfo me = fleet_.self();
  std::vector<msg::DaemonInfo> now = fleet_.others();
  now.push_back(me);
  for (const msg::DaemonInfo& d : now) {
    const std::string id = d.server_id().to_string();
    if (id != self_ && wire::holds(d, scene) && wire::outweighs(scene, d, me, now)) {
      release(scene);
      fleet_.announce();
      throw InputError(kRequest, "scene",
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

void SceneClaims::remember_holders(const std::vector<msg::DaemonInfo>& others) {
  for (const msg::DaemonInfo& d : others) {
    for (const auto& name : d.loaded()) {
      const std::string scene = name.to_string();
      if (held_by_.size() >= kMaxRemembered && !held_by_.count(scene)) continue;
      held_by_[scene] = d.server_id().to_string();
      const msg::StoredRoadmap* r = wire::roadmap_of(d, scene);
      accepted_[scene] = r ? std::max(r->samples(), r->target()) : 0;
    }
  }
}

void SceneClaims::add_handovers(const std::vector<msg::DaemonInfo>& others, const msg::DaemonInfo& me,
                                std::vector<OrphanScene>& out) {
  const auto now = std::chrono::steady_clock::now();
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
      OrphanScene orphan{scene, d.server_id().to_string(), true, std::nullopt, accepted};
      if (const auto s = last_status_.find(scene); s != last_status_.end() && s->second.server_id() == d.server_id()) {
        orphan.last_status = s->second;
      }
      out.push_back(std::move(orphan));
    }
  }
}

void SceneClaims::retry_takeovers(const std::vector<msg::DaemonInfo>& others,
                                  const std::vector<msg::DaemonInfo>& everyone, std::vector<OrphanScene>& out) {
  const auto now = std::chrono::steady_clock::now();
  for (auto it = takeovers_.begin(); it != takeovers_.end();) {
    auto& [scene, pending] = *it;
    if (claimed_.count(scene) || !wire::holder_of(scene, others).empty() ||
        wire::assigned_daemon(scene, everyone) != self_) {
      it = takeovers_.erase(it);  // taken over (here or elsewhere), or no longer this daemon's
      continue;
    }
    if (now - pending.reported >= retry_delay(pending.attempts)) {  // the takeover failed: once more
      pending.reported = now;
      ++pending.attempts;
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
  remember_holders(others);
  for (auto it = held_by_.begin(); it != held_by_.end();) {
    const auto& [scene, holder] = *it;
    const std::string now_held = wire::holder_of(scene, others);
    if (now_held == holder) {
      ++it;  // still held by the daemon last seen holding it
    } else if (!now_held.empty() || claimed_.count(scene) || alive(others, holder)) {
      it = held_by_.erase(it);  // moved to another daemon, or here, or released (handed over: below)
    } else if (wire::assigned_daemon(scene, everyone) == self_) {
      OrphanScene orphan{scene, holder, false, std::nullopt, accepted_[scene]};
      if (const auto s = last_status_.find(scene); s != last_status_.end() && s->second.server_id() == holder) {
        orphan.last_status = s->second;
      }
      if (takeovers_.size() < kMaxRemembered) takeovers_[scene] = {orphan, std::chrono::steady_clock::now()};
      out.push_back(std::move(orphan));
      it = held_by_.erase(it);
    } else {
      ++it;  // another live daemon is to take it over; remembered in case it leaves too
    }
  }
  retry_takeovers(others, everyone, out);
  add_handovers(others, everyone.back(), out);
  return out;
}

std::chrono::seconds SceneClaims::takeover_retry_in(const std::string& scene) const {
  std::lock_guard lock(mutex_);
  const auto it = takeovers_.find(scene);
  return it == takeovers_.end() ? std::chrono::seconds(0) : retry_delay(it->second.attempts);
}

void SceneClaims::observe(const msg::DaemonInfo& announcement) {
  if (announcement.server_id() == self_) return;
  std::lock_guard lock(mutex_);
  remember_holders({announcement});
}

void SceneClaims::observe(const msg::SceneStatus& status) {
  // An UNLOADED status (also sent by a daemon stopping) says nothing of the roadmap it held.
  if (status.server_id() == self_ || status.state() == msg::SCENE_UNLOADED) return;
  std::lock_guard lock(mutex_);
  const std::string scene = status.scene().to_string();
  if (last_status_.size() < kMaxRemembered || last_status_.count(scene)) {
    last_status_[scene] = status;
  }
}

}  // namespace ispars::server
