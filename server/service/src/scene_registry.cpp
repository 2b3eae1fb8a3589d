#include "ispars/service/scene_registry.hpp"

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "request_input.hpp"

namespace ispars::service {

SceneRegistry::Reservation::~Reservation() {
  if (added_) return;
  std::lock_guard lock(registry_.mutex_);
  registry_.loading_.erase(name_);
}

void SceneRegistry::Reservation::add(std::shared_ptr<RoadmapSession> session) {
  std::lock_guard lock(registry_.mutex_);
  registry_.sessions_.emplace(name_, std::move(session));
  registry_.loading_.erase(name_);
  added_ = true;
}

std::unique_ptr<SceneRegistry::Reservation> SceneRegistry::reserve(const std::string& name) {
  std::lock_guard lock(mutex_);
  if (sessions_.count(name) || !loading_.insert(name).second) {
    throw params::InputError(kRequest, "scene", fmt::format("scene '{}' is already loaded or being loaded", name));
  }
  return std::unique_ptr<Reservation>(new Reservation(*this, name));
}

std::shared_ptr<RoadmapSession> SceneRegistry::find(const std::string& name) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(name);
  return it == sessions_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<RoadmapSession>> SceneRegistry::sessions() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<RoadmapSession>> out;
  out.reserve(sessions_.size());
  for (const auto& [name, s] : sessions_) out.push_back(s);
  return out;
}

std::vector<std::string> SceneRegistry::names() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  out.reserve(sessions_.size());
  for (const auto& [name, s] : sessions_) out.push_back(name);
  return out;
}

std::vector<std::string> SceneRegistry::held_or_loading() const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out(loading_.begin(), loading_.end());
  for (const auto& [name, s] : sessions_) out.push_back(name);
  return out;
}

void SceneRegistry::erase(const std::string& name) {
  std::shared_ptr<RoadmapSession> gone;  // let go outside the lock: a last holder's teardown waits for no reader
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(name);
  if (it == sessions_.end()) return;
  gone = std::move(it->second);
  sessions_.erase(it);
}

}  // namespace ispars::service
