#include "ispars/service/build_job.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "ispars/planning/builders/poi_visibility.hpp"
#include "ispars/planning/builders/recipe_builder.hpp"
#include "ispars/service/session_recovery.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars::service {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::unique_ptr<planning::RoadmapBuilder> builder_for(const planning::Scene& scene, const RoadmapRecipe& recipe,
                                                      unsigned threads) {
  return planning::make_roadmap_builder(recipe.method, scene, planning::recipe_build_options(recipe, threads));
}

// A replay stopped by a cancel or by the daemon stopping: nothing stored is touched, and the
// scene stays as it was (idle), not failed.
struct ReplayInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace

BuildJob::BuildJob(JobSite site, SessionRecord& record, CommitCallback on_commit)
    : site_(site), record_(record), on_commit_(std::move(on_commit)) {}

void BuildJob::adopt(std::unique_ptr<RoadmapStore> store, std::optional<planning::BuiltRoadmaps> resume_from) {
  store_ = std::move(store);
  recovered_ = std::move(resume_from);
}

void BuildJob::clear() {
  builder_.reset();
  build_scene_.reset();
  recovered_.reset();
}

std::optional<RoadmapsView> BuildJob::roadmaps() const {
  if (builder_) return live_view();
  if (recovered_) {
    return RoadmapsView{recovered_->samples, &recovered_->roadmap, recovered_->dense ? &*recovered_->dense : nullptr,
                        recovered_->dense_ids};
  }
  return std::nullopt;
}

RoadmapsView BuildJob::live_view() const {
  return {builder_->samples(), &builder_->roadmap(), builder_->dense(), builder_->dense_ids()};
}

DenseCounts BuildJob::dense_counts() const {
  const Roadmap* dense = builder_->dense();
  return dense ? DenseCounts{dense->vertex_count(), dense->edge_count()} : DenseCounts{};
}

void BuildJob::announce(const BuildCommit& commit, std::uint64_t generation) const {
  if (on_commit_) on_commit_(commit.roadmap, generation, commit.samples, builder_->roadmap().poi_count());
}

void BuildJob::run(const std::atomic<bool>& stopping) {
  bool changed = false;
  std::optional<SessionJob> job = record_.take(stopping, changed);
  if (!job) {
    if (changed) record_.notify();
    return;
  }
  // A build or a task is in the status as accepted until its first commit; a stopping daemon's
  // last status keeps it, since the job is recorded and resumed at the restart.
  record_.start(*job);
  struct ForgetStarting {
    SessionRecord& record;
    const std::atomic<bool>& stopping;
    ~ForgetStarting() { record.forget_starting(stopping); }
  } forget{record_, stopping};
  Run run{std::move(*job)};
  try {
    perform(run, stopping);
  } catch (const ReplayInterrupted& e) {
    // The builder was being rebuilt from the recipe; the store and what is served are untouched.
    builder_.reset();
    build_scene_.reset();
    record_.interrupt_replay(e.what());
  } catch (const planning::AdditionStopped& e) {
    task_stopped(fmt::format("task '{}' not added: {} ({})", run.job.task->name,
                             record_.cancelled() ? "cancelled" : "the daemon is stopping", e.what()),
                 e.builder_changed, stopping);
  } catch (const std::exception& e) {
    fail(run.job.task ? fmt::format("task '{}' not added: {}", run.job.task->name, e.what()) : e.what());
  }
  record_.notify();
}

void BuildJob::perform(Run& run, const std::atomic<bool>& stopping) {
  prepare(run, stopping);
  if (run.job.task) {
    record_.begin(SessionState::building);
    add_task(run, stopping);
    end(run, stopping);
    record_.notify();
    return;
  }
  const std::uint64_t target = builder_->samples() + run.job.samples;
  // A new roadmap's target shows from its first commit on (record_chunk).
  record_.begin(SessionState::building, run.job.build ? std::nullopt : std::optional(target));
  grow(run, target, stopping);
  end(run, stopping);
}

void BuildJob::task_stopped(const std::string& why, bool builder_changed, bool stopping) {
  // Nothing of the task was committed: what the session serves is as before, and the scene is
  // idle without the task.
  if (builder_changed && !stopping) {
    // The builder's roadmaps are part way: the store is reopened (as after a failure), so the
    // next job resumes from what it holds.
    fail(why);
  } else {
    // Unchanged, it goes on serving; changed, with the daemon stopping, it is dropped (the
    // store is whole, and nothing is reopened on the way out).
    if (builder_changed) builder_.reset();
    record_.fail(why);
  }
  record_.settle_failure(why);
}

void BuildJob::prepare(Run& run, const std::atomic<bool>& stopping) {
  const SessionJob& job = run.job;
  if (job.build) {
    // The old roadmap (if any) stays published and stored until this build's first commit: the
    // new store is made aside and takes its place then (RoadmapStore::create).
    store_.reset();
    clear();
    build_scene_ =
        std::make_unique<planning::Scene>(session_detail::scene_for(*record_.scene_with_tasks(), job.recipe));
    builder_ = builder_for(*build_scene_, job.recipe, site_.limits.build_threads);
    store_ = RoadmapStore::create(site_.store_dir, job.recipe, site_.fs);
    store_->set_compact_every(site_.limits.compact_every);
    return;
  }
  if (!store_) {
    // It could not be reopened for writing after an earlier failure (a read-only filesystem,
    // say), and the last commit was served from a read: try again now, or fail saying why.
    StoreRecovery reopened;
    store_ = RoadmapStore::open(site_.store_dir, site_.scene.pois().size(), reopened, site_.fs);
    store_->set_compact_every(site_.limits.compact_every);
  }
  ensure_builder(stopping);
  run.roadmap_version = builder_->roadmap().version();
  run.dense_version = builder_->dense() ? builder_->dense()->version() : 0;
}

planning::BuiltRoadmaps BuildJob::resumable_roadmaps(const RoadmapRecipe& recipe) {
  // As recovered after a restart or a failure; for a method whose roadmap alone is its state,
  // else the published copy of the last commit.
  planning::BuiltRoadmaps built;
  if (recovered_) {
    built = std::move(*recovered_);
    recovered_.reset();
    return built;
  }
  const SessionRoadmap served = record_.served();
  const PublishedRoadmap& p = served.published;
  if (p.generation != recipe.generation || !p.roadmap || p.samples != served.samples_done) {
    throw std::runtime_error("the published roadmap is not the last commit: cannot resume from it");
  }
  built.roadmap = *p.roadmap;
  built.samples = p.samples;
  return built;
}

void BuildJob::ensure_builder(const std::atomic<bool>& stopping) {
  if (builder_) return;
  const SessionRoadmap served = record_.served();
  const RoadmapRecipe& recipe = *served.recipe;
  build_scene_ = std::make_unique<planning::Scene>(session_detail::scene_for(*served.scene_with_tasks, recipe));
  if (!planning::resumes_from_roadmap(recipe.method) &&
      !(planning::resumes_without_replay(recipe.method) && recovered_)) {
    replay(recipe, stopping);
    return;
  }
  // Its stored roadmaps are its whole state: it goes on from them, with nothing replayed.
  const auto t0 = std::chrono::steady_clock::now();
  builder_ = planning::resume_roadmap_builder(recipe.method, *build_scene_,
                                              planning::recipe_build_options(recipe, site_.limits.build_threads),
                                              resumable_roadmaps(recipe));
  spdlog::info(
      "scene '{}': the {} builder resumed from its stored roadmaps at {} samples in {:.3f} s, nothing replayed",
      site_.name, to_string(recipe.method), builder_->samples(), seconds_since(t0));
}

void BuildJob::replay(const RoadmapRecipe& recipe, const std::atomic<bool>& stopping) {
  record_.begin(SessionState::replaying);
  auto builder = builder_for(*build_scene_, recipe, site_.limits.build_threads);
  const std::uint64_t target = recovered_ ? recovered_->samples : 0;
  while (builder->samples() < target) {
    if (stopping || record_.cancelled()) {
      throw ReplayInterrupted(fmt::format("{} during the replay, at {} of {} samples",
                                          record_.cancelled() ? "cancelled" : "daemon stopped", builder->samples(),
                                          target));
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

void BuildJob::grow(Run& run, std::uint64_t target, const std::atomic<bool>& stopping) {
  // Commit in chunks of about a quarter second: often enough for live progress and a small
  // loss on a crash, rarely enough that fsync and publishing stay a small share of the time.
  const SessionJob& job = run.job;
  std::uint64_t chunk = 64;
  auto last_copy = std::chrono::steady_clock::now() - std::chrono::hours(1);
  double copy_seconds = 0.0;
  bool first = job.build.has_value();  // a new roadmap commits at least its first chunk (the root)
  while (first || (builder_->samples() < target && !stopping && !record_.cancelled())) {
    const auto t0 = std::chrono::steady_clock::now();
    builder_->extend(std::min(chunk, target - builder_->samples()));
    const RoadmapsView view = live_view();
    BuildCommit commit = commit_since(view, run.roadmap_version, run.dense_version);
    // A new roadmap keeps the scene's tasks: it is built with their POIs, and its first commit
    // records them.
    if (job.build && first) set_tasks(commit, record_.tasks());
    store_->commit(commit);
    run.roadmap_version = view.roadmap->version();
    run.dense_version = view.dense ? view.dense->version() : 0;
    // Readers get an immutable copy. A copy costs time in the roadmap's size, so it is taken
    // only when the last one is older than ten times its own cost (at least every 5 s, and
    // always at the end): publishing stays a small share of the build however large it grows.
    ChunkRecord done{job.build && first ? job.build : std::nullopt, target, builder_->samples(), {}, dense_counts()};
    const bool last_chunk = builder_->samples() >= target || stopping || record_.cancelled();
    if (last_chunk || seconds_since(last_copy) >= std::min(5.0, std::max(0.25, 10.0 * copy_seconds))) {
      const auto c0 = std::chrono::steady_clock::now();
      done.copy =
          make_published(std::make_shared<const Roadmap>(*view.roadmap), job.recipe.generation, builder_->samples());
      copy_seconds = seconds_since(c0);
      last_copy = std::chrono::steady_clock::now();
    }
    record_.record_chunk(std::move(done));
    announce(commit, job.recipe.generation);
    record_.notify();
    const double took = seconds_since(t0);
    if (took < 0.1) chunk = std::min<std::uint64_t>(chunk * 2, 100'000);
    if (took > 0.5) chunk = std::max<std::uint64_t>(chunk / 2, 16);
    first = false;
  }
}

void BuildJob::add_task(Run& run, const std::atomic<bool>& stopping) {
  const InspectionTask& task = *run.job.task;
  const auto t0 = std::chrono::steady_clock::now();
  auto widened = std::make_unique<planning::Scene>(build_scene_->with_more_pois(task.pois));
  auto next = std::make_shared<const planning::Scene>(record_.scene_with_tasks()->with_more_pois(task.pois));
  const std::uint64_t task_count = record_.task_events() + 1;
  const std::size_t guards = builder_->add_pois(*widened, [&] { return !stopping && !record_.cancelled(); });
  build_scene_ = std::move(widened);  // the builder plans in it from now on
  const RoadmapsView view = live_view();
  BuildCommit commit = commit_since(view, run.roadmap_version, run.dense_version);
  commit.tasks = {task};
  commit.task_count = task_count;
  store_->commit(commit);  // durable: from here on the task is the roadmap's
  run.roadmap_version = view.roadmap->version();
  run.dense_version = view.dense ? view.dense->version() : 0;
  record_.record_task(
      task, std::move(next),
      make_published(std::make_shared<const Roadmap>(*view.roadmap), run.job.recipe.generation, builder_->samples()),
      dense_counts());
  announce(commit, run.job.recipe.generation);
  spdlog::info("scene '{}': task '{}' added ({} POIs, {} guards) in {:.3f} s", site_.name, task.name, task.pois.size(),
               guards, seconds_since(t0));
}

void BuildJob::end(const Run& run, bool stopping) {
  const std::uint64_t generation = run.job.recipe.generation;
  if (!record_.publishes(generation, builder_->samples(), builder_->roadmap().version())) {
    // A cancel or a stop that came after a chunk's copy was decided (no copy) ended the loop:
    // readers would see an older roadmap than the status's samples. They get the last commit.
    record_.publish(
        make_published(std::make_shared<const Roadmap>(builder_->roadmap()), generation, builder_->samples()));
  }
  if (run.job.recipe.method == BuildMethod::dense) {
    // A Dense builder resumes from the published copy of its last commit: an idle Dense scene
    // holds its roadmap once, not twice. (ispars2 keeps its builder: its route cache makes the
    // next extend's first samples cheaper than a resumed builder's.)
    builder_.reset();
    build_scene_.reset();
    ::malloc_trim(0);  // hand the freed adjacency back to the system, not to a later build
  }
  record_.end_job(stopping);
}

void BuildJob::fail(std::string error) {
  // Whatever the builder holds past the last commit is not trusted: reopen the store.
  clear();
  store_.reset();
  const planning::Scene& scene = site_.scene;
  std::optional<StoreRecovery> recovery;
  try {
    if (site_.fs.exists(site_.store_dir)) {
      recovery.emplace();
      store_ = RoadmapStore::open(site_.store_dir, scene.pois().size(), *recovery, site_.fs);
      store_->set_compact_every(site_.limits.compact_every);
    }
  } catch (const std::exception& reopen) {
    error += std::string("; reopening the store failed: ") + reopen.what();
    recovery.reset();
    store_.reset();
    // Not writable (a read-only filesystem, say) but readable: serve its last commit.
    try {
      if (site_.fs.exists(site_.store_dir))
        recovery = RoadmapStore::read(site_.store_dir, scene.pois().size(), site_.fs);
    } catch (const std::exception&) {
      recovery.reset();
    }
  }
  std::optional<StoredRoadmap> stored;
  if (recovery) {
    try {
      stored = serve_recovery(scene, *recovery, site_.limits.build_threads, recovered_);
    } catch (const std::exception& e) {
      error += std::string("; the stored tasks' POIs could not be seen: ") + e.what();
      store_.reset();
      recovered_.reset();
    }
  }
  // What the store holds now is the truth: make everything the session shows agree with it.
  record_.take_stored(std::move(stored), SessionState::failed, std::move(error));
}

}  // namespace ispars::service
