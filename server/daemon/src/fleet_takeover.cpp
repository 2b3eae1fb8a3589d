// Taking a scene over: this daemon's own copy continued when it is the same roadmap, the former
// owner's rebuilt from its recipe otherwise (builds are deterministic), an older copy set aside;
// and the task changes of a copy handed here, or continued, carried in.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

#include "ispars/server/dds_link.hpp"
#include "ispars/server/fleet_member.hpp"
#include "ispars/server/status_message.hpp"
#include "ispars/server/takeover_plan.hpp"
#include "ispars/server/task_merge.hpp"
#include "ispars/wire/scene_owner.hpp"

namespace ispars::server {
namespace {

// The samples of the roadmap `status` describes: its target while it was still building, and
// the target a stopping daemon's job had accepted (idle, the job recorded to resume); a queued
// build's samples (accepted_generation), of which nothing is done yet.
std::uint64_t samples_to_rebuild(const msg::SceneStatus& status) {
  if (status.accepted_generation() != 0) return status.samples_target();
  return std::max(status.samples_target(), status.samples_done());
}

}  // namespace

void FleetMember::start_takeovers(std::vector<OrphanScene> orphans) {
  for (OrphanScene& orphan : orphans) {
    // A scene taken over now is reported again after its retry period, should this one fail.
    if (takeovers_.running(orphan.scene)) continue;
    std::erase_if(waiting_takeovers_, [&](const OrphanScene& o) { return o.scene == orphan.scene; });
    waiting_takeovers_.push_back(std::move(orphan));
  }
  if (waiting_takeovers_.empty()) return;
  const std::vector<msg::DaemonInfo> others = dds_.other_daemons();
  const std::vector<std::string> claimed = claims_->claimed();
  for (auto it = waiting_takeovers_.begin(); it != waiting_takeovers_.end();) {
    // One that waited for a runner may be stale: held elsewhere now, or taken over here.
    const bool here = std::find(claimed.begin(), claimed.end(), it->scene) != claimed.end();
    if (!wire::holder_of(it->scene, others).empty() || (here && !it->handed_over)) {
      it = waiting_takeovers_.erase(it);
    } else if (takeovers_.start(it->scene, [this, orphan = *it] { take_over(orphan); })) {
      it = waiting_takeovers_.erase(it);  // SceneClaims sees it run (Fleet::taking_over)
    } else {
      break;  // every runner busy: the next pass
    }
  }
}

void FleetMember::take_over(const OrphanScene& orphan) {
  spdlog::warn("daemon {} {} scene '{}'; this daemon takes it over", orphan.former_owner,
               orphan.handed_over ? "handed over" : "left while holding", orphan.scene);
  const auto held = takeover_gate_.hold(orphan.scene);  // until the former owner's work is resumed here
  try {
    const auto [session, loaded_now] = service_->load(orphan.scene);
    FormerRoadmap former;
    former.owner = orphan.former_owner;
    former.samples = orphan.accepted;
    if (const auto& st = orphan.last_status) {
      former.recipe = recipe_of(*st);  // a queued build's (accepted_generation), else the roadmap's
      former.fingerprint = st->scene_fingerprint().to_string();
      former.builder_version = st->builder_version();
      // The samples its announcement accepted count only for the lineage the status names.
      const std::uint64_t lineage = former.recipe ? former.recipe->generation : st->generation();
      if (orphan.accepted_generation != 0 && orphan.accepted_generation != lineage) former.samples = 0;
      former.samples = std::max(former.samples, samples_to_rebuild(*st));
      former.generation = st->generation();
      former.task_events = st->task_events();
      if (former.task_events > 0) {  // published under the roadmap's generation
        // POIs not checked: an acknowledged task not yet committed counts in task_events, not in poi_count.
        former.tasks =
            task_board_.tasks_of(orphan.scene, orphan.former_owner, st->generation(), former.task_events, std::nullopt);
      }
    }
    const TakeoverPlan plan = plan_takeover(orphan.scene, session->status(), session->fingerprint(), former);
    if (plan.set_aside) {
      const auto where = service_->set_aside(orphan.scene, plan.outcome);
      spdlog::warn("scene '{}': this daemon's copy is kept aside in {}", orphan.scene, where.string());
    }
    if (plan.action == TakeoverPlan::Action::extend) service_->extend(orphan.scene, plan.extend_by);
    // A continued copy of the former owner's lineage: its task changes are merged in once idle.
    if (const auto mine = session->status().recipe; plan.action != TakeoverPlan::Action::rebuild && !plan.refused &&
                                                    former.tasks && !former.tasks->empty() && mine &&
                                                    mine->generation == former.generation) {
      std::lock_guard lock(carried_mutex_);
      carried_tasks_[orphan.scene] = {former.owner, *former.tasks};
    }
    if (plan.action == TakeoverPlan::Action::rebuild) {
      if (!plan.tasks.empty()) service_->adopt_tasks(orphan.scene, plan.tasks);
      service_->build(orphan.scene, plan.request);
    }
    listing_.set_note(orphan.scene, plan.outcome);
    if (plan.refused) {
      spdlog::warn("{}", plan.outcome);
    } else {
      spdlog::info("{}", plan.outcome);
    }
  } catch (const std::exception& e) {
    failed_takeover(orphan, e.what());
  }
}

void FleetMember::failed_takeover(const OrphanScene& orphan, const std::string& what) {
  // Not held empty: the claim is released (so no user starts a new lineage on an empty scene
  // thinking it served), the reason is in the scenes list, and the takeover is tried again.
  // Declined until the retry, and before the release is announced: the rule names the next
  // daemon meanwhile (one with room, say), and no daemon takes the release for one on purpose.
  const auto retry = claims_->takeover_retry_in(orphan.scene);
  listing_.decline(orphan.scene, std::chrono::steady_clock::now() + retry);
  bool released = false;
  try {
    const service::SessionStatus st = service_->stats(orphan.scene);
    if (!st.recipe) {
      service_->unload(orphan.scene);
      released = true;
    }
  } catch (const std::exception&) {
    released = true;  // never loaded
  }
  const std::string note =
      fmt::format("taking over scene '{}' from daemon {} failed: {}; {}{}", orphan.scene, orphan.former_owner, what,
                  released ? "released" : "kept as held",
                  retry.count() > 0 ? fmt::format(", tried again in {} s while nobody holds it", retry.count()) : "");
  listing_.set_note(orphan.scene, note);
  spdlog::error("{}", note);
  announce();
}

void FleetMember::merge_handed_tasks() {
  std::optional<std::vector<service::ServedRoadmap>> held;  // read only when some copy with tasks was handed here
  for (const msg::DaemonInfo& d : dds_.other_daemons()) {
    for (const msg::StoredRoadmap& r : d.roadmaps()) {
      const std::string scene = r.scene().to_string();
      if (r.yielded_to().to_string() != config_.server_id || r.task_events() == 0 || wire::holds(d, scene)) continue;
      if (!held) held = service_->held_roadmaps();
      const auto mine =
          std::find_if(held->begin(), held->end(), [&](const service::ServedRoadmap& h) { return h.scene == scene; });
      if (mine == held->end() || mine->generation != r.generation()) continue;
      const std::string from = d.server_id().to_string();
      const std::string key = fmt::format("{} {} {} {}", from, r.generation(), r.task_events(), mine->task_events);
      if (const auto merged = tasks_merged_.find(scene); merged != tasks_merged_.end() && merged->second == key)
        continue;
      const auto theirs = task_board_.tasks_of(scene, from, r.generation(), r.task_events(), std::nullopt);
      if (!theirs) continue;  // not all arrived yet: looked at again on the next pass
      if (apply_task_merge(scene, from, *theirs)) tasks_merged_[scene] = key;
    }
  }
  std::map<std::string, CarriedTasks> carried;  // written by takeovers on their own threads
  {
    std::lock_guard lock(carried_mutex_);
    carried = carried_tasks_;
  }
  const std::vector<std::string> loaded = carried.empty() ? std::vector<std::string>{} : service_->loaded_scenes();
  for (const auto& [scene, c] : carried) {
    const bool here = std::find(loaded.begin(), loaded.end(), scene) != loaded.end();
    if (here && !apply_task_merge(scene, c.from, c.tasks)) continue;
    std::lock_guard lock(carried_mutex_);
    if (const auto it = carried_tasks_.find(scene); it != carried_tasks_.end() && it->second.from == c.from) {
      carried_tasks_.erase(it);  // unless a takeover carried another owner's meanwhile
    }
  }
}

bool FleetMember::apply_task_merge(const std::string& scene, const std::string& from,
                                   std::span<const service::InspectionTask> theirs) {
  // One change a pass: an addition is a job, and the scene takes one job at a time.
  try {
    const auto session = service_->session(scene);
    if (session->busy()) return false;  // a job runs: the next pass
    const TaskMerge merge = merge_tasks(session->tasks(), theirs);
    if (merge.empty()) return true;
    if (!merge.remove.empty()) {
      (void)service_->remove_task(scene, merge.remove.front());
      spdlog::warn("scene '{}': task '{}' removed, as daemon {}, whose copy this daemon holds now, had removed it",
                   scene, merge.remove.front(), from);
    } else {
      (void)service_->add_task(scene, merge.add.front());
      spdlog::warn("scene '{}': task '{}' added, as daemon {}, whose copy this daemon holds now, had added it", scene,
                   merge.add.front().name, from);
    }
    return false;
  } catch (const std::exception& e) {  // refused: not loaded, a job started meanwhile, a task refused
    try {
      if (service_->session(scene)->busy()) return false;  // the next pass
    } catch (const std::exception&) {
      // not loaded any more: given up below
    }
    spdlog::error("scene '{}': carrying daemon {}'s task changes failed: {}", scene, from, e.what());
    return true;  // not tried again until either list changes
  }
}

}  // namespace ispars::server
