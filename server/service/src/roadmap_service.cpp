// The roadmap service's scenes and changes: loading and unloading sessions, builds and extends
// scheduled on the build workers, cancel and drop. Queries that take time (snapshots, tours,
// verification) are in roadmap_service_queries.cpp.

#include "ispars/service/roadmap_service.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/record_file.hpp"
#include "ispars/service/drop_mark.hpp"
#include "ispars/service/pending_jobs.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "ispars/service/scene_catalog.hpp"
#include "request_input.hpp"

namespace ispars::service {
RoadmapService::RoadmapService(ServiceSettings settings, ServiceEvents events, FileSystem& fs)
    : settings_(std::move(settings)),
      events_(std::move(events)),
      fs_(fs),
      budget_(MemoryBudget::make(settings_.memory_budget_bytes)),
      snapshots_(budget_, [this] { return !readers_stopped_.load(); }),
      jobs_(settings_.build_workers, settings_.data_dir, fs_, stopping_),
      tours_(settings_.tour_workers, settings_.tours_per_worker, budget_, stopping_) {
  if (!std::filesystem::is_directory(settings_.scene_dir)) {
    throw std::runtime_error("scene directory " + settings_.scene_dir.string() + " does not exist");
  }
  // A data directory made here is durable before anything in it is (its name is in its parent).
  if (fs_.create_directories(settings_.data_dir)) fsync_directory_of(settings_.data_dir, fs_);
  remove_dropped_stores(settings_.data_dir, fs_);
  budget_->set_reclaimer([this] { snapshots_.drop_all(); });
  if (settings_.scrub_period.count() > 0) {
    // Sessions held and being loaded are left alone: their stores are written.
    scrub_ = std::make_unique<StoreScrub>(
        settings_.data_dir, [this] { return scenes_.held_or_loading(); }, budget_, settings_.scrub_period, fs_);
  }
}

RoadmapService::~RoadmapService() { stop(); }

std::string RoadmapService::scrub_problem(const std::string& scene) const {
  return scrub_ ? scrub_->problem(scene) : std::string();
}

void RoadmapService::stop() {
  if (stopping_.exchange(true)) return;
  if (scrub_) scrub_->stop();
  tours_.stop("");
  stop_all_readers("the daemon is stopping");
  jobs_.stop_workers();  // running builds commit their current chunk and return
  tours_.close();        // running tours stop early and report their best
  jobs_.mark_stopped_cleanly();
  for (const auto& name : scenes_.names()) {
    if (events_.release) events_.release(name);
    if (events_.on_unloaded) events_.on_unloaded(name, /*given_up=*/false);
  }
}

void RoadmapService::load_stored_roadmaps() {
  for (const std::string& name : fs_.list(settings_.data_dir)) {
    const std::filesystem::path dir = settings_.data_dir / name;
    if (!valid_scene_name(name) || !fs_.exists(dir / "recipe.json")) continue;
    if (marked_unloaded(dir, fs_)) {
      spdlog::info("scene '{}' has a stored roadmap but was unloaded; a load request loads it", name);
      continue;
    }
    try {
      if (!session_or_null(name)) open_session(name);
    } catch (const std::exception& e) {
      spdlog::error("stored roadmap of scene '{}' not reloaded: {}", name, e.what());
    }
  }
}

std::vector<SceneListing> RoadmapService::list_scenes() const {
  std::vector<SceneListing> out;
  for (const std::string& name : list_scene_names(settings_.scene_dir)) {
    SceneListing e;
    e.name = name;
    if (const auto session = scenes_.find(name)) {
      e.loaded = true;
      e.has_roadmap = session->status().recipe.has_value();
    } else {
      e.has_roadmap = fs_.exists(settings_.data_dir / name / "recipe.json");
    }
    out.push_back(std::move(e));
  }
  return out;
}

std::vector<std::string> RoadmapService::loaded_scenes() const { return scenes_.names(); }

std::shared_ptr<RoadmapSession> RoadmapService::session_or_null(const std::string& scene) const {
  return scenes_.find(scene);
}

std::shared_ptr<RoadmapSession> RoadmapService::session(const std::string& scene) const {
  if (auto s = session_or_null(scene)) return s;
  if (!valid_scene_name(scene)) (void)scene_file(settings_.scene_dir, scene);  // names the bad name
  throw params::InputError(kRequest, "scene",
                           fmt::format("scene '{}' is not loaded on daemon {}", scene, settings_.server_id));
}

SessionStatus RoadmapService::stats(const std::string& scene) const { return session(scene)->status(); }

planning::RoadmapPath RoadmapService::path(const std::string& scene, const Vec3& from, const Vec3& to) const {
  return session(scene)->path(from, to);
}

std::shared_ptr<RoadmapSession> RoadmapService::open_session(const std::string& name) {
  (void)scene_file(settings_.scene_dir, name);  // names a bad name before anything is reserved
  // Reserve the name: two concurrent loads must not both open the scene's store.
  const auto reservation = scenes_.reserve(name);
  if (events_.claim) events_.claim(name);
  struct Unclaim {
    const ServiceEvents& events;
    const std::string& name;
    bool held = false;
    ~Unclaim() {
      if (!held && events.release) events.release(name);
    }
  } unclaim{events_, name};
  planning::Scene scene = planning::Scene::build(load_scene_config(settings_.scene_dir, name));
  SessionCallbacks callbacks;
  callbacks.on_commit = [this, name](const RoadmapBatch& batch, std::uint64_t generation, std::uint64_t samples,
                                     std::size_t poi_count) {
    if (events_.on_commit) events_.on_commit(name, batch, generation, samples, poi_count);
  };
  callbacks.on_status = [this, name](const SessionStatus&) {
    if (!events_.on_status) return;
    if (const auto s = session_or_null(name)) events_.on_status(*s);
  };
  callbacks.admit_cost = [budget = budget_, name](const planning::BuildCost& cost) { budget->admit(name, cost); };
  auto session = std::make_shared<RoadmapSession>(name, std::move(scene), settings_.data_dir / name, settings_.limits,
                                                  std::move(callbacks), fs_);
  mark_unloaded(settings_.data_dir / name, false, fs_);
  budget_->set_reserved(name, session->expected_cost().peak_bytes);  // a stored roadmap is held whatever the budget
  reservation->add(session);
  unclaim.held = true;
  if (!session->recovery_note().empty()) spdlog::info("scene '{}': {}", name, session->recovery_note());
  if (!session->torn_tail_note().empty()) spdlog::warn("scene '{}': {}", name, session->torn_tail_note());
  // A refused store is damage: said where operators look, not only in the scene's status.
  if (const SessionStatus st = session->status(); st.state == SessionState::failed) {
    spdlog::error("scene '{}': its stored roadmap is refused, and left as it is: {}", name, st.last_error);
  }
  spdlog::info("loaded scene '{}' ({} triangles, {} POIs)", name, session->scene().mesh().triangle_count(),
               session->scene().pois().size());
  if (events_.on_status) events_.on_status(*session);
  if (events_.on_scenes_changed) events_.on_scenes_changed();
  return session;
}

std::pair<std::shared_ptr<RoadmapSession>, bool> RoadmapService::load(const std::string& scene) {
  if (auto s = session_or_null(scene)) return {s, false};
  return {open_session(scene), true};
}

void RoadmapService::unload(const std::string& scene) {
  const auto s = session(scene);
  if (s->busy()) {
    throw params::InputError(kRequest, "scene",
                             fmt::format("a build is running on scene '{}'; cancel it first", scene));
  }
  // Remembered across restarts: the stored roadmap stays, but is not reloaded until asked. Marked
  // first: a mark that cannot be written (a read-only disk) leaves the scene loaded as it was.
  mark_unloaded(settings_.data_dir / scene, true, fs_);
  try {
    s->close();  // atomically with the busy check inside: no job can start on it any more
  } catch (...) {
    mark_unloaded(settings_.data_dir / scene, false, fs_);
    throw;
  }
  forget(scene, /*given_up=*/false);
}

void RoadmapService::stop_readers(const std::string& scene, const std::string& why) {
  if (const auto s = session_or_null(scene)) s->stop_readers(why);
}

void RoadmapService::stop_all_readers(const std::string& why) {
  readers_stopped_ = true;  // snapshot encodings stop too (at their next slice)
  for (const auto& s : scenes_.sessions()) s->stop_readers(why);
}

void RoadmapService::yield(const std::string& scene, const std::atomic<bool>& give_up) {
  const auto s = session_or_null(scene);
  if (!s) return;
  tours_.stop(scene);
  // A running build stops after its current chunk (within half a second), a queued one and any
  // verify at once. Bounded: a scene that will not close in kYieldWait stays, and the fleet's next
  // pass asks again.
  const auto deadline = std::chrono::steady_clock::now() + kYieldWait;
  for (;;) {
    if (stopping_ || give_up) return;         // stop() reports every scene unloaded
    if (session_or_null(scene) != s) return;  // unloaded (or unloaded and loaded again) meanwhile
    s->stop_readers(fmt::format("scene '{}' is being given up to its owner", scene));
    (void)s->cancel();
    try {
      s->close();
      break;
    } catch (const params::InputError& e) {
      if (std::chrono::steady_clock::now() >= deadline) {
        spdlog::warn("scene '{}' not given up to its owner within {} s: {}", scene,
                     std::chrono::duration_cast<std::chrono::seconds>(kYieldWait).count(), e.what());
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  jobs_.forget(scene, 0);  // the owner builds it now
  forget(scene, /*given_up=*/true);
  spdlog::warn("scene '{}' given up to its owner (its stored roadmap stays)", scene);
}

void RoadmapService::forget(const std::string& scene, bool given_up) {
  // The claim goes first: a load racing this one then claims anew instead of reusing a claim
  // about to be released.
  if (events_.release) events_.release(scene);
  scenes_.erase(scene);
  budget_->set_reserved(scene, 0.0);
  if (events_.on_unloaded) events_.on_unloaded(scene, given_up);
  if (events_.on_scenes_changed) events_.on_scenes_changed();
}

std::vector<ServedRoadmap> RoadmapService::held_roadmaps() const {
  std::vector<ServedRoadmap> out;
  for (const auto& s : scenes_.sessions()) {
    const SessionStatus st = s->status();
    ServedRoadmap r{s->name(), s->published().generation, 0, 0, "", true};
    if (!st.recipe && r.generation == 0) continue;  // nothing built (or a store it refused): no copy
    if (st.recipe) {
      r.generation = st.recipe->generation;
      r.samples = st.samples_done;
      r.target = std::max(st.samples_done, st.samples_target);
      r.fingerprint = st.recipe->scene_fingerprint;
      r.task_events = st.task_events;
    }
    if (st.accepted) {  // a queued build: its lineage, nothing of it committed yet
      r.generation = st.accepted->generation;
      r.samples = 0;
      r.target = st.samples_target;
      r.fingerprint = st.accepted->scene_fingerprint;
    }
    out.push_back(std::move(r));
  }
  return out;
}

std::filesystem::path RoadmapService::set_aside(const std::string& scene, const std::string& why) {
  return session(scene)->set_aside(why);
}

void RoadmapService::adopt_tasks(const std::string& scene, std::vector<InspectionTask> tasks) {
  session(scene)->adopt_tasks(std::move(tasks));
}

namespace {

// Why a stored copy built on `recipe`'s scene file cannot be served from this daemon's scene file
// as it is now; empty when it can (or when either fingerprint is unknown: a store older than them).
std::string fingerprint_problem(const RoadmapRecipe& recipe, const CurrentFingerprint& now) {
  if (recipe.scene_fingerprint.empty() || (now.fingerprint.empty() && now.problem.empty())) return "";
  if (!now.problem.empty()) return fmt::format("{}; its stored roadmap is not offered to the fleet", now.problem);
  if (now.fingerprint == recipe.scene_fingerprint) return "";
  return fmt::format(
      "its stored roadmap was built on another version of the scene file (fingerprint {} there, {} "
      "in this daemon's scene file): not offered to the fleet (restore the file, or build with replace)",
      recipe.scene_fingerprint, now.fingerprint);
}

}  // namespace

StoredListing list_stored_roadmaps(const std::filesystem::path& data_dir, const std::vector<std::string>& loaded,
                                   SceneFingerprints* current,
                                   const std::function<std::string(const std::string&)>& scrubbed) {
  StoredListing out;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(data_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory() || !valid_scene_name(name) || !std::filesystem::exists(entry.path() / "recipe.json")) {
      continue;
    }
    out.scenes.push_back(name);
    try {
      const RoadmapRecipe recipe = RoadmapStore::read_recipe(entry.path());
      if (recipe.builder_version != 0 && recipe.builder_version != kBuilderVersion) {
        out.unservable.push_back(
            {name, fmt::format("its stored roadmap was made by builder version {}, and this daemon "
                               "has version {}: not offered to the fleet (rebuild or drop it)",
                               recipe.builder_version, kBuilderVersion)});
        continue;
      }
      if (std::find(loaded.begin(), loaded.end(), name) != loaded.end()) continue;  // weighed live
      std::string damage = store_quick_problem(entry.path());
      if (damage.empty() && scrubbed) damage = scrubbed(name);
      if (!damage.empty()) {
        out.unservable.push_back({name, fmt::format("its stored roadmap is damaged: {}; not offered to the fleet "
                                                    "(drop it, or build with replace)",
                                                    damage)});
        continue;
      }
      if (std::string problem = fingerprint_problem(recipe, current ? current->of(name) : CurrentFingerprint{});
          !problem.empty()) {
        out.unservable.push_back({name, std::move(problem)});
        continue;
      }
      const auto head = read_store_head(entry.path());
      const bool head_current = head && head->generation == recipe.generation;
      const std::uint64_t samples = head_current ? head->samples : 0;
      out.served.push_back({name, recipe.generation, samples, samples, recipe.scene_fingerprint, false,
                            head_current ? head->task_events : 0});
    } catch (const std::exception& e) {
      out.unservable.push_back({name, fmt::format("its stored roadmap cannot be read: {}", e.what())});
    }
  }
  // A scene dropped here and not built since: its empty roadmap, weighed by the drop's generation.
  for (const DropMark& mark : list_drop_marks(data_dir)) {
    if (!valid_scene_name(mark.scene) || std::filesystem::exists(data_dir / mark.scene / "recipe.json") ||
        std::find(loaded.begin(), loaded.end(), mark.scene) != loaded.end()) {
      continue;
    }
    out.served.push_back({mark.scene, mark.generation, 0, 0, "", false});
  }
  std::sort(out.scenes.begin(), out.scenes.end());
  std::sort(out.served.begin(), out.served.end(),
            [](const ServedRoadmap& a, const ServedRoadmap& b) { return a.scene < b.scene; });
  return out;
}

CancelOutcome RoadmapService::cancel(const std::string& scene) {
  const auto s = session(scene);
  CancelOutcome out;
  out.build_cancelled = s->cancel();
  out.tours_stopped = tours_.stop(scene);
  jobs_.forget(scene, 0);  // cancelled: never resumed, whether it ends before the daemon stops or not
  return out;
}

void RoadmapService::drop(const std::string& scene) {
  session(scene)->drop();
  jobs_.forget(scene, 0);
  budget_->set_reserved(scene, 0.0);
}

}  // namespace ispars::service
