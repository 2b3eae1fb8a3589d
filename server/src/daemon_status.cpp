// What isparsd tells the domain: each scene's status, stamped in order, and the daemon's own
// announcement (host, pid, scenes available and loaded).

#include <unistd.h>

#include "daemon.hpp"
#include "dds_endpoints.hpp"
#include "ispars/service/scene_catalog.hpp"
#include "status_message.hpp"

namespace ispars::server {

msg::SceneStatus Daemon::status_message(const RoadmapSession& session) const {
  // Stamped under one lock with the reading, so a later stamp is never an older state.
  std::lock_guard lock(status_mutex_);
  msg::SceneStatus m = to_message(session.status(), config_.server_id, session.published().generation);
  m.status_seq(++status_seq_);
  return m;
}

void Daemon::publish_status(const std::string& scene) {
  if (!dds_) return;
  const auto s = session_or_null(scene);
  if (!s) return;
  std::lock_guard lock(publish_mutex_);
  dds_->publish_status(status_message(*s));
}

void Daemon::publish_unloaded(const std::string& name) {
  msg::SceneStatus status;
  status.scene(name);
  status.server_id(config_.server_id);
  status.state(msg::SCENE_UNLOADED);
  std::lock_guard lock(publish_mutex_);
  {
    std::lock_guard stamp(status_mutex_);
    status.status_seq(++status_seq_);
  }
  dds_->publish_status(status);
}

void Daemon::announce() {
  msg::DaemonInfo info;
  info.server_id(config_.server_id);
  info.host(host_name());
  info.pid(static_cast<std::int32_t>(::getpid()));
  info.available(list_scene_names(config_.scene_dir));
  {
    std::lock_guard lock(sessions_mutex_);
    for (const auto& [name, s] : sessions_) info.loaded().push_back(name);
  }
  dds_->announce(info);
}

}  // namespace ispars::server
