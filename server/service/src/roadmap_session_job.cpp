// A session's build job: resuming a builder from the stored roadmaps after a restart (IRIS-C:
// replaying its recipe), then growing the roadmap chunk by chunk, each chunk committed to the
// store, published, and reported.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "ispars/builders/poi_visibility.hpp"
#include "ispars/builders/recipe_builder.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/session_recovery.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::unique_ptr<RoadmapBuilder> builder_for(const Scene& scene, const RoadmapRecipe& recipe, unsigned threads) {
  return make_roadmap_builder(recipe.method, scene, recipe_build_options(recipe, threads));
}

// A replay stopped by a cancel or by the daemon stopping: nothing stored is touched, and the
// scene stays as it was (idle), not failed.
struct ReplayInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

RoadmapsView RoadmapSession::live_view() const {
  return {builder_->samples(), &builder_->roadmap(), builder_->dense(), builder_->dense_ids()};
}

bool RoadmapSession::published_is_builders(std::uint64_t generation) const {
  std::lock_guard lock(mutex_);
  return published_.roadmap && published_.generation == generation && published_.samples == builder_->samples() &&
         published_.roadmap->version() == builder_->roadmap().version();
}

std::uint64_t RoadmapSession::samples_done() const {
  std::lock_guard lock(mutex_);
  return samples_done_;
}

void RoadmapSession::ensure_builder(const std::atomic<bool>& stopping) {
  if (builder_) return;
  RoadmapRecipe recipe;
  {
    std::lock_guard lock(mutex_);
    recipe = *recipe_;
  }
  build_scene_ = std::make_unique<Scene>(session_detail::scene_for(*scene_with_tasks(), recipe));
  if (resumes_from_roadmap(recipe.method) || (resumes_without_replay(recipe.method) && recovered_)) {
    // Its stored roadmaps are its whole state: it goes on from them (as recovered after a restart
    // or a failure; for a method whose roadmap alone is its state, else the published copy of the
    // last commit), with nothing replayed.
    const auto t0 = std::chrono::steady_clock::now();
    BuiltRoadmaps built;
    if (recovered_) {
      built = std::move(*recovered_);
    } else {
      PublishedRoadmap p;
      {
        std::lock_guard lock(mutex_);
        p = published_;
      }
      if (p.generation != recipe.generation || !p.roadmap || p.samples != samples_done()) {
        throw std::runtime_error("the published roadmap is not the last commit: cannot resume from it");
      }
      built.roadmap = *p.roadmap;
      built.samples = p.samples;
    }
    recovered_.reset();
    builder_ = resume_roadmap_builder(recipe.method, *build_scene_, recipe_build_options(recipe, limits_.build_threads),
                                      std::move(built));
    spdlog::info(
        "scene '{}': the {} builder resumed from its stored roadmaps at {} samples in {:.3f} s, nothing replayed",
        name_, to_string(recipe.method), builder_->samples(),
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return;
  }
  {
    std::lock_guard lock(mutex_);
    state_ = SessionState::replaying;
  }
  notify_status();
  auto builder = builder_for(*build_scene_, recipe, limits_.build_threads);
  const std::uint64_t target = recovered_ ? recovered_->samples : 0;
  while (builder->samples() < target) {
    if (stopping || cancel_) {
      throw ReplayInterrupted(fmt::format("{} during the replay, at {} of {} samples",
                                          cancel_ ? "cancelled" : "daemon stopped", builder->samples(), target));
    }
    builder->extend(std::min<std::uint64_t>(5000, target - builder->samples()));
  }
  if (recovered_) {
    const bool same = builder->roadmap().same_changes_as(recovered_->roadmap) &&
                      (builder->dense() == nullptr) == !recovered_->dense.has_value() &&
                      (builder->dense() == nullptr || builder->dense()->same_changes_as(*recovered_->dense)) &&
                      std::equal(builder->dense_ids().begin(), builder->dense_ids().end(),
                                 recovered_->dense_ids.begin(), recovered_->dense_ids.end());
    if (!same) {
      throw std::runtime_error(
          fmt::format("replaying the recipe to {} samples did not reproduce the stored roadmap", target));
    }
  }
  builder_ = std::move(builder);
  recovered_.reset();
}

void RoadmapSession::run_job(const std::atomic<bool>& stopping) {
  // A running verify stops (a job is a writer of the roadmaps it reads); new ones are refused
  // while the job is queued or runs (lock_idle_job).
  readers_->stop_all(fmt::format("a build started on scene '{}'", name_));
  std::lock_guard job_lock(job_mutex_);
  std::optional<Job> job = take_job(stopping);
  if (!job) return;
  // A build or a task is in the status as accepted until its first commit (status_locked); a stopping
  // daemon's last status keeps it, since the job is recorded and resumed at the restart.
  struct ForgetStartingBuild {
    RoadmapSession& session;
    const std::atomic<bool>& stopping;
    ~ForgetStartingBuild() {
      std::lock_guard lock(session.mutex_);
      if (stopping) return;
      session.starting_build_.reset();
      session.starting_task_.reset();
    }
  } forget{*this, stopping};
  {
    std::lock_guard lock(mutex_);
    if (job->build) {
      starting_build_ = job->recipe;
      starting_samples_ = job->samples;
    }
    if (job->task) starting_task_ = job->task;  // likewise a task, until it is committed
  }
  try {
    perform_job(*job, stopping);
  } catch (const ReplayInterrupted& e) {
    // The builder was being rebuilt from the recipe; the store and what is served are untouched.
    builder_.reset();
    build_scene_.reset();
    std::lock_guard lock(mutex_);
    last_error_ = e.what();
    samples_target_ = samples_done_;
    state_ = SessionState::idle;
    cancel_ = false;
  } catch (const AdditionStopped& e) {
    task_stopped(fmt::format("task '{}' not added: {} ({})", job->task->name,
                             cancel_ ? "cancelled" : "the daemon is stopping", e.what()),
                 e.builder_changed, stopping);
  } catch (const std::exception& e) {
    fail_job(job->task ? fmt::format("task '{}' not added: {}", job->task->name, e.what()) : e.what());
  }
  notify_status();
}

void RoadmapSession::perform_job(Job& job, const std::atomic<bool>& stopping) {
  prepare_job(job, stopping);
  if (job.task) {
    {
      std::lock_guard lock(mutex_);
      state_ = SessionState::building;
    }
    notify_status();
    add_task(job, stopping);
    end_job(job, stopping);
    notify_status();
    return;
  }
  const std::uint64_t target = builder_->samples() + job.samples;
  {
    std::lock_guard lock(mutex_);
    // A new roadmap's target shows from its first commit on, with its recipe: until then the
    // status describes the old roadmap only (a takeover rebuilds from the status).
    if (!job.build) samples_target_ = target;
    state_ = SessionState::building;
  }
  notify_status();
  grow(job, target, stopping);
  end_job(job, stopping);
}

void RoadmapSession::task_stopped(const std::string& why, bool builder_changed, const std::atomic<bool>& stopping) {
  // Nothing of the task was committed: what the session serves is as before, and the scene is
  // idle without the task.
  if (builder_changed && !stopping) {
    // The builder's roadmaps are part way: the store is reopened (as after a failure), so the
    // next job resumes from what it holds.
    fail_job(why);
  } else {
    // Unchanged, it goes on serving; changed, with the daemon stopping, it is dropped (the
    // store is whole, and nothing is reopened on the way out).
    if (builder_changed) builder_.reset();
    std::lock_guard lock(mutex_);
    last_error_ = why;
    state_ = SessionState::failed;
  }
  std::lock_guard lock(mutex_);
  if (state_ == SessionState::failed && last_error_ == why) state_ = recipe_ ? SessionState::idle : SessionState::empty;
  cancel_ = false;
}

std::optional<RoadmapSession::Job> RoadmapSession::take_job(const std::atomic<bool>& stopping) {
  Job job;
  {
    std::lock_guard lock(mutex_);
    if (state_ != SessionState::queued) return std::nullopt;
    job.build = pending_recipe_;
    job.samples = pending_samples_;
    job.task = std::move(pending_task_);
    pending_recipe_.reset();
    pending_samples_ = 0;
    pending_task_.reset();
    if (!cancel_ && !stopping) {
      job.recipe = job.build ? *job.build : *recipe_;
      // Taken from the queue: a cancel from now on reaches the job (cancel_), not the queue. While
      // the builder comes back (ensure_builder) the job is already running.
      state_ = SessionState::building;
      return job;
    }
    // Cancelled while queued: nothing is touched.
    state_ = recipe_ ? SessionState::idle : SessionState::empty;
    samples_target_ = samples_done_;
    last_error_ = cancel_ ? "cancelled before it started" : "daemon stopped before the job started";
    cancel_ = false;
  }
  notify_status();
  return std::nullopt;
}

void RoadmapSession::prepare_job(Job& job, const std::atomic<bool>& stopping) {
  if (job.build) {
    // The old roadmap (if any) stays published and stored until this build's first commit: the
    // new store is made aside and takes its place then (RoadmapStore::create).
    store_.reset();
    builder_.reset();
    recovered_.reset();
    build_scene_ = std::make_unique<Scene>(session_detail::scene_for(*scene_with_tasks(), job.recipe));
    builder_ = builder_for(*build_scene_, job.recipe, limits_.build_threads);
    store_ = RoadmapStore::create(store_dir_, job.recipe, fs_);
    store_->set_compact_every(limits_.compact_every);
    return;
  }
  if (!store_) {
    // It could not be reopened for writing after an earlier failure (a read-only filesystem,
    // say), and the last commit was served from a read: try again now, or fail saying why.
    StoreRecovery reopened;
    store_ = RoadmapStore::open(store_dir_, scene_.pois().size(), reopened, fs_);
    store_->set_compact_every(limits_.compact_every);
  }
  ensure_builder(stopping);
  job.roadmap_version = builder_->roadmap().version();
  job.dense_version = builder_->dense() ? builder_->dense()->version() : 0;
}

void RoadmapSession::grow(Job& job, std::uint64_t target, const std::atomic<bool>& stopping) {
  // Commit in chunks of about a quarter second: often enough for live progress and a small
  // loss on a crash, rarely enough that fsync and publishing stay a small share of the time.
  std::uint64_t chunk = 64;
  auto last_copy = std::chrono::steady_clock::now() - std::chrono::hours(1);
  double copy_seconds = 0.0;
  bool first = job.build.has_value();  // a new roadmap commits at least its first chunk (the root)
  while (first || (builder_->samples() < target && !stopping && !cancel_)) {
    const auto t0 = std::chrono::steady_clock::now();
    builder_->extend(std::min(chunk, target - builder_->samples()));
    const RoadmapsView view = live_view();
    BuildCommit commit = commit_since(view, job.roadmap_version, job.dense_version);
    if (job.build && first) {
      // A new roadmap keeps the scene's tasks: it is built with their POIs, and its first commit
      // records them.
      std::lock_guard lock(mutex_);
      set_tasks(commit, tasks_);
    }
    store_->commit(commit);
    job.roadmap_version = view.roadmap->version();
    job.dense_version = view.dense ? view.dense->version() : 0;
    // Readers get an immutable copy. A copy costs time in the roadmap's size, so it is taken
    // only when the last one is older than ten times its own cost (at least every 5 s, and
    // always at the end): publishing stays a small share of the build however large it grows.
    const bool last_chunk = builder_->samples() >= target || stopping || cancel_;
    std::optional<PublishedRoadmap> copy;
    if (last_chunk || seconds_since(last_copy) >= std::min(5.0, std::max(0.25, 10.0 * copy_seconds))) {
      const auto c0 = std::chrono::steady_clock::now();
      copy = make_published(std::make_shared<const Roadmap>(*view.roadmap), job.recipe.generation, builder_->samples());
      copy_seconds = seconds_since(c0);
      last_copy = std::chrono::steady_clock::now();
    }
    {
      std::lock_guard lock(mutex_);
      if (job.build && first) {  // the new roadmap is stored: it replaces the old one everywhere now
        recipe_ = job.recipe;
        samples_target_ = target;
        damage_.clear();  // a damaged store, if there was one, was discarded by this build (replace)
      }
      samples_done_ = builder_->samples();
      if (copy) published_ = std::move(*copy);
      dense_vertices_ = view.dense ? view.dense->vertex_count() : 0;
      dense_edges_ = view.dense ? view.dense->edge_count() : 0;
    }
    if (callbacks_.on_commit) {
      callbacks_.on_commit(commit.roadmap, job.recipe.generation, commit.samples, view.roadmap->poi_count());
    }
    notify_status();
    const double took = seconds_since(t0);
    if (took < 0.1) chunk = std::min<std::uint64_t>(chunk * 2, 100'000);
    if (took > 0.5) chunk = std::max<std::uint64_t>(chunk / 2, 16);
    first = false;
  }
}

void RoadmapSession::end_job(const Job& job, const std::atomic<bool>& stopping) {
  if (!published_is_builders(job.recipe.generation)) {
    // A cancel or a stop that came after a chunk's copy was decided (no copy) ended the loop:
    // readers would see an older roadmap than the status's samples. They get the last commit.
    auto copy = make_published(std::make_shared<const Roadmap>(builder_->roadmap()), job.recipe.generation,
                               builder_->samples());
    std::lock_guard lock(mutex_);
    published_ = std::move(copy);
  }
  if (job.recipe.method == BuildMethod::dense) {
    // A Dense builder resumes from the published copy of its last commit: an idle Dense scene
    // holds its roadmap once, not twice. (ispars2 keeps its builder: its route cache makes the
    // next extend's first samples cheaper than a resumed builder's.)
    builder_.reset();
    build_scene_.reset();
    ::malloc_trim(0);  // hand the freed adjacency back to the system, not to a later build
  }
  std::lock_guard lock(mutex_);
  if (cancel_) last_error_ = fmt::format("cancelled at {} of {} samples", samples_done_, samples_target_);
  if (stopping && samples_done_ < samples_target_) {
    last_error_ = fmt::format("daemon stopped at {} of {} samples", samples_done_, samples_target_);
  }
  // A stopping daemon's job stays accepted (recorded, resumed at its restart): its target stays
  // in the last status and announcement, so the daemon that takes the scene over reaches it.
  if (!stopping) samples_target_ = samples_done_;
  state_ = SessionState::idle;
  cancel_ = false;
}

void RoadmapSession::fail_job(std::string error) {
  // Whatever the builder holds past the last commit is not trusted: reopen the store.
  builder_.reset();
  build_scene_.reset();
  store_.reset();
  recovered_.reset();
  std::optional<StoreRecovery> recovery;
  std::shared_ptr<const Scene> with_tasks = std::make_shared<const Scene>(scene_);
  try {
    if (fs_.exists(store_dir_)) {
      recovery.emplace();
      store_ = RoadmapStore::open(store_dir_, scene_.pois().size(), *recovery, fs_);
      store_->set_compact_every(limits_.compact_every);
    }
  } catch (const std::exception& reopen) {
    error += std::string("; reopening the store failed: ") + reopen.what();
    recovery.reset();
    store_.reset();
    // Not writable (a read-only filesystem, say) but readable: serve its last commit.
    try {
      if (fs_.exists(store_dir_)) recovery = RoadmapStore::read(store_dir_, scene_.pois().size(), fs_);
    } catch (const std::exception&) {
      recovery.reset();
    }
  }
  if (recovery) {
    try {
      with_tasks = complete_tasks(scene_, *recovery, limits_.build_threads);
    } catch (const std::exception& e) {
      error += std::string("; the stored tasks' POIs could not be seen: ") + e.what();
      recovery.reset();
      store_.reset();
    }
  }
  // What the store holds now is the truth: make everything the session shows agree with it.
  std::lock_guard lock(mutex_);
  last_error_ = std::move(error);
  scene_with_tasks_ = with_tasks;
  if (recovery) {
    tasks_ = std::move(recovery->tasks);
    recipe_ = recovery->recipe;
    samples_done_ = recovery->roadmaps.samples;
    published_ =
        make_published(std::make_shared<const Roadmap>(recovery->roadmaps.roadmap), recipe_->generation, samples_done_);
    dense_vertices_ = recovery->roadmaps.dense ? recovery->roadmaps.dense->vertex_count() : 0;
    dense_edges_ = recovery->roadmaps.dense ? recovery->roadmaps.dense->edge_count() : 0;
    recovered_ = std::move(recovery->roadmaps);
  } else {
    recipe_.reset();
    tasks_.clear();
    published_ = make_published(std::make_shared<const Roadmap>(scene_.pois().size()), 0, 0);
    samples_done_ = 0;
    dense_vertices_ = dense_edges_ = 0;
  }
  samples_target_ = samples_done_;
  state_ = SessionState::failed;
  cancel_ = false;
}

}  // namespace ispars
