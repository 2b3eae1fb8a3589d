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
  if (const std::string holder = wire::holder_of(scene, others); !holder.empty()) {
    throw InputError(kRequest, "scene", fmt::format("scene '{}' is owned by daemon {}", scene, holder));
  }
  std::vector<msg::DaemonInfo> everyone = others;
  everyone.push_back(fleet_.self());
  if (const std::string assigned = wire::assigned_daemon(scene, everyone); assigned != self_) {
    const bool stored = std::any_of(everyone.begin(), everyone.end(), [&](const msg::DaemonInfo& d) {
      return d.server_id() == assigned && wire::stores(d, scene);
    });
    throw InputError(kRequest, "scene",
                     fmt::format("scene '{}' belongs to daemon {} by the fleet's rule (the live daemon offering it "
                                 "with the highest rendezvous weight{}); load it there (ispars does by itself)",
                                 scene, assigned, stored ? ", among those with a stored roadmap of it" : ""));
  }
  {
    std::lock_guard lock(mutex_);
    claimed_.insert(scene);
  }
  fleet_.announce();
  std::this_thread::sleep_for(kClaimWindow);
  for (const msg::DaemonInfo& d : fleet_.others()) {
    const std::string id = d.server_id().to_string();
    if (wire::holds(d, scene) && wire::outranks(scene, id, self_)) {
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

std::vector<std::string> SceneClaims::contested() const {
  const std::vector<msg::DaemonInfo> others = fleet_.others();
  std::vector<std::string> out;
  for (const std::string& scene : claimed()) {
    for (const msg::DaemonInfo& d : others) {
      if (wire::holds(d, scene) && wire::outranks(scene, d.server_id().to_string(), self_)) {
        out.push_back(scene);
        break;
      }
    }
  }
  return out;
}

std::vector<OrphanScene> SceneClaims::orphans() {
  const std::vector<msg::DaemonInfo> others = fleet_.others();
  std::vector<msg::DaemonInfo> everyone = others;
  everyone.push_back(fleet_.self());
  std::vector<OrphanScene> out;
  std::lock_guard lock(mutex_);
  for (const msg::DaemonInfo& d : others) {
    for (const auto& scene : d.loaded()) {
      if (held_by_.size() < kMaxRemembered || held_by_.count(scene.to_string())) {
        held_by_[scene.to_string()] = d.server_id().to_string();
      }
    }
  }
  for (auto it = held_by_.begin(); it != held_by_.end();) {
    const auto& [scene, holder] = *it;
    const std::string now_held = wire::holder_of(scene, others);
    if (now_held == holder) {
      ++it;  // still held by the daemon last seen holding it
    } else if (!now_held.empty() || claimed_.count(scene) || alive(others, holder)) {
      it = held_by_.erase(it);  // moved to another daemon, or here, or released on purpose
    } else if (wire::assigned_daemon(scene, everyone) == self_) {
      OrphanScene orphan{scene, holder, std::nullopt};
      if (const auto s = last_status_.find(scene); s != last_status_.end() && s->second.server_id() == holder) {
        orphan.last_status = s->second;
      }
      out.push_back(std::move(orphan));
      it = held_by_.erase(it);
    } else {
      ++it;  // another live daemon is to take it over; remembered in case it leaves too
    }
  }
  return out;
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
