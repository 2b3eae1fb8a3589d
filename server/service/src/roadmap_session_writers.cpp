// A session's writers outside its build job: a task's removal and adoption, a drop, a set-aside
// (the fleet's), and the unload. Those that take a roadmap away stop running readers first
// (ReaderGate), then take the job lock alone.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/drop_mark.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "request_input.hpp"

namespace ispars::service {

std::size_t RoadmapSession::remove_task(const std::string& name) {
  // The store has one writer: a job holds job_mutex_ alone from its start to its end (and for a
  // moment after its status turns idle). Shared with verifies, which only read; two removals are
  // kept apart by removal_mutex_. The commit waits on the disk outside the record's lock, which
  // every status read takes: what it reads there cannot change meanwhile (no job runs, and
  // removals are one at a time).
  const auto job_lock = lock_idle_job<std::shared_lock<std::shared_mutex>>("remove the task");
  std::lock_guard removal(removal_mutex_);
  const auto [index, task_events_after] = record_.check_removal(name, job_.store() != nullptr);
  const SessionRoadmap served = record_.served();
  // A commit that changes no vertex or edge: the roadmaps' versions stay; it marks the task.
  BuildCommit commit;
  commit.samples = served.samples_done;
  commit.roadmap.from_version = commit.roadmap.to_version = served.published.roadmap->version();
  commit.dense.from_version = commit.dense.to_version = served.dense.vertices + served.dense.edges;
  commit.removed_tasks = {index};
  commit.task_count = task_events_after;
  job_.store()->commit(commit);  // durable before the reply: a removal acknowledged is never lost
  const std::size_t after = record_.mark_removed(index);
  spdlog::info("scene '{}': task '{}' removed", name_, name);
  return after;
}

void RoadmapSession::adopt_tasks(std::vector<InspectionTask> tasks) {
  record_.check_adoptable();
  // Checked against the scene's own mesh (a task's POIs lie on it): no lock is held meanwhile,
  // and the takeover that calls this is the only writer of an empty scene.
  std::vector<InspectionTask> checked;
  for (InspectionTask& t : tasks) {
    const bool removed = t.removed;
    t.removed = false;
    check_task(scene_, checked, t);
    t.removed = removed;
    checked.push_back(std::move(t));
  }
  auto with_tasks = std::make_shared<const planning::Scene>(scene_.with_more_pois(task_pois(checked)));
  record_.adopt_tasks(std::move(checked), std::move(with_tasks));
}

void RoadmapSession::drop() { (void)discard_store(""); }

std::filesystem::path RoadmapSession::set_aside(const std::string& why) { return discard_store(why); }

std::filesystem::path RoadmapSession::discard_store(const std::string& aside_why) {
  const char* what = aside_why.empty() ? "drop" : "set aside";
  // Running verifies stop, and new ones wait outside, so the job lock comes free at once.
  const auto readers_off = readers_->hold_off(fmt::format("scene '{}' is being dropped", name_));
  const auto job = lock_idle_job<std::unique_lock<std::shared_mutex>>(what);
  const std::uint64_t empty_generation = record_.begin_discard();  // no request is accepted meanwhile
  std::unique_ptr<RoadmapStore> store = job_.release_store();
  // Joining a compaction and removing files take time: not under the record's lock, which every
  // status and STATS takes. The job lock (held alone) keeps jobs and readers of the builder out.
  std::filesystem::path aside;
  try {
    mark_dropped(store_dir_, empty_generation, fs_);  // first: a failure leaves the store as it was
  } catch (...) {
    job_.restore_store(std::move(store));
    record_.end_discard();
    throw;
  }
  try {
    store.reset();
    job_.clear();
    if (aside_why.empty()) {
      drop_store(store_dir_, fs_);
    } else {
      aside = set_aside_store(store_dir_, aside_why, fs_);
    }
  } catch (...) {
    record_.end_discard();
    throw;
  }
  record_.discarded(empty_generation);
  return aside;
}

void RoadmapSession::close() {
  const auto readers_off = readers_->hold_off(fmt::format("scene '{}' is being unloaded", name_));
  const auto job = lock_idle_job<std::unique_lock<std::shared_mutex>>("unload");
  record_.close();
  // The store's lock goes now, not when the last holder of this session lets go (a tour still
  // running on the published roadmap, say): the scene can be loaded again at once. Its
  // compaction is joined outside the record's lock, so STATS and statuses never wait for it.
  job_.release_store().reset();
  job_.clear();
}

}  // namespace ispars::service
