#include "ispars/server/status_publisher.hpp"

#include "ispars/server/status_message.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

// The tasks of a scene as the fleet reads them (ispars/tasks), for its status's roadmap.
std::vector<msg::SceneTask> task_messages(const std::vector<service::InspectionTask>& tasks,
                                          const msg::SceneStatus& status) {
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

StatusPublisher::StatusPublisher(std::string server_id, DaemonOutbox& out, DaemonMetrics& metrics,
                                 const std::atomic<bool>& leaving)
    : server_id_(std::move(server_id)), out_(out), metrics_(metrics), leaving_(leaving) {}

std::uint64_t StatusPublisher::next_seq() const {
  std::lock_guard lock(stamp_mutex_);
  return ++seq_;
}

msg::SceneStatus StatusPublisher::status_message(const service::RoadmapSession& session) const {
  // Stamped under one lock with the reading, so a later stamp is never an older state.
  std::lock_guard lock(stamp_mutex_);
  msg::SceneStatus m = to_message(session.status(), server_id_, session.published().generation);
  m.status_seq(++seq_);
  return m;
}

void StatusPublisher::publish_status(const service::RoadmapSession& session) {
  std::lock_guard lock(publish_mutex_);
  const msg::SceneStatus status = status_message(session);
  metrics_.observe_samples(status.scene().to_string(), status.samples_done());
  out_.publish_status(status);
  if (status.task_events() == 0) return;
  out_.publish_tasks(status.scene().to_string(), status.generation(), status.task_events(),
                     [&] { return task_messages(session.accepted_tasks(), status); });
}

void StatusPublisher::publish_unloaded(const std::string& scene, bool given_up) {
  // A stopping daemon leaves its updates as they are: its writer goes with its participant. (Its
  // last batches may still be in flight on the asynchronous writer, and removing them from the
  // history just before the writer is deleted crashed the daemon now and then at SIGTERM.)
  if (!leaving_) out_.retire_updates(scene);
  if (given_up) return;  // the owner's statuses are the scene's: no stale UNLOADED after them
  msg::SceneStatus status;
  status.scene(scene);
  status.server_id(server_id_);
  status.state(msg::SCENE_UNLOADED);
  std::lock_guard lock(publish_mutex_);
  status.status_seq(next_seq());
  out_.publish_status(status);
}

void StatusPublisher::publish_commit(const std::string& scene, const RoadmapBatch& batch, std::uint64_t generation,
                                     std::uint64_t samples, std::size_t poi_count) {
  msg::UpdateBatch update = wire::to_message(batch, scene, server_id_, generation, samples);
  update.poi_count(static_cast<std::uint32_t>(poi_count));
  out_.publish_update(update);
}

void StatusPublisher::republish(const std::string& scene, const service::RoadmapSession& session) {
  publish_status(session);
  // An empty batch at the roadmap's version: one behind sees a gap and resyncs; one up to date
  // takes it for a duplicate.
  const service::SessionStatus status = session.status();
  if (!status.recipe) return;
  msg::UpdateBatch mark;
  mark.scene(scene);
  mark.server_id(server_id_);
  mark.generation(session.published().generation);
  mark.from_version(status.version);
  mark.to_version(status.version);
  mark.samples_done(status.samples_done);
  mark.first_edge(static_cast<std::uint32_t>(status.edges));
  out_.publish_update(mark);
}

}  // namespace ispars::server
