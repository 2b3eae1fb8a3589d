// What isparsd tells the domain: the service's events as messages. Each scene's status, stamped
// in order; committed batches as updates; and the daemon's own announcement (protocol, host, pid,
// scenes claimed; the scene files and stored roadmaps come from its FleetListing).

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>

#include "daemon.hpp"
#include "dds_endpoints.hpp"
#include "ispars/wire/convert.hpp"
#include "status_message.hpp"

namespace ispars::server {
namespace {

// The tasks of a scene as the fleet reads them (ispars/tasks), for its status's roadmap.
std::vector<msg::SceneTask> task_messages(const std::vector<InspectionTask>& tasks, const msg::SceneStatus& status) {
  std::vector<msg::SceneTask> out;
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    msg::SceneTask m;
    m.scene(status.scene());
    m.index(static_cast<std::uint32_t>(i));
    m.server_id(status.server_id());
    m.generation(status.generation());
    m.name(tasks[i].name);
    m.removed(tasks[i].removed);
    for (const Vec3& p : tasks[i].pois) m.pois().push_back(wire::to_message(p));
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace

ServiceEvents Daemon::service_events() {
  ServiceEvents events;
  events.on_commit = [this](const std::string& scene, const RoadmapBatch& batch, std::uint64_t generation,
                            std::uint64_t samples, std::size_t poi_count) {
    msg::UpdateBatch update = wire::to_message(batch, scene, config_.server_id, generation, samples);
    update.poi_count(static_cast<std::uint32_t>(poi_count));
    with_dds([&](DdsEndpoints& d) { d.publish_update(update); });
  };
  events.on_status = [this](const RoadmapSession& session) { publish_status(session); };
  events.on_unloaded = [this](const std::string& scene, bool given_up) { publish_unloaded(scene, given_up); };
  events.on_scenes_changed = [this] { announce(); };
  events.claim = [this](const std::string& scene) {
    claims_->claim(scene);
    listing_.held_again(scene);
  };
  events.release = [this](const std::string& scene) {
    claims_->release(scene);
    // A stopping daemon keeps its last announcement: it vanishes with the daemon, and the
    // fleet takes its scenes over as after a crash.
    if (!leaving_) announce();
  };
  return events;
}

msg::SceneStatus Daemon::status_message(const RoadmapSession& session) const {
  // Stamped under one lock with the reading, so a later stamp is never an older state.
  std::lock_guard lock(status_mutex_);
  msg::SceneStatus m = to_message(session.status(), config_.server_id, session.published().generation);
  m.status_seq(++status_seq_);
  return m;
}

void Daemon::publish_status(const RoadmapSession& session) {
  std::lock_guard lock(publish_mutex_);
  const msg::SceneStatus status = status_message(session);
  metrics_.observe_samples(status.scene().to_string(), status.samples_done());
  with_dds([&](DdsEndpoints& d) {
    d.publish_status(status);
    if (status.task_events() == 0) return;
    d.publish_tasks(status.scene().to_string(), status.generation(), status.task_events(),
                    [&] { return task_messages(session.accepted_tasks(), status); });
  });
}

void Daemon::publish_unloaded(const std::string& scene, bool given_up) {
  // A stopping daemon leaves its updates as they are: its writer goes with its participant. (Its
  // last batches may still be in flight on the asynchronous writer, and removing them from the
  // history just before the writer is deleted crashed the daemon now and then at SIGTERM.)
  if (!leaving_) with_dds([&](DdsEndpoints& d) { d.retire_updates(scene); });
  if (given_up) return;  // the owner's statuses are the scene's: no stale UNLOADED after them
  msg::SceneStatus status;
  status.scene(scene);
  status.server_id(config_.server_id);
  status.state(msg::SCENE_UNLOADED);
  std::lock_guard lock(publish_mutex_);
  {
    std::lock_guard stamp(status_mutex_);
    status.status_seq(++status_seq_);
  }
  with_dds([&](DdsEndpoints& d) { d.publish_status(status); });
}

msg::DaemonInfo Daemon::self_info() const {
  msg::DaemonInfo info;
  info.server_id(config_.server_id);
  info.protocol(msg::PROTOCOL_VERSION);
  info.version(ISPARS_VERSION);
  info.host(host_name());
  info.pid(static_cast<std::int32_t>(::getpid()));
  info.joined_ms(joined_ms_);
  info.builder_version(kBuilderVersion);
  listing_.describe(info, service_ ? service_->held_roadmaps() : std::vector<ServedRoadmap>{});
  // Claimed scenes (being loaded or loaded) are announced as held: no other daemon claims them.
  for (const std::string& name : claims_->claimed()) info.loaded().push_back(name);
  return info;
}

bool Daemon::refresh_listing() {
  if (!service_) return listing_.refresh(std::nullopt);
  return listing_.refresh(service_->loaded_scenes(),
                          [this](const std::string& scene) { return service_->scrub_problem(scene); });
}

void Daemon::announce() {
  std::lock_guard lock(announce_mutex_);  // the latest state is the last written
  refresh_listing();
  const msg::DaemonInfo info = self_info();
  with_dds([&](DdsEndpoints& d) { d.announce(info); });
}

}  // namespace ispars::server
