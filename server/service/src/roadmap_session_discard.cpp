// A session's writers that take a roadmap away: a drop, a set-aside (the fleet's), and the
// unload. Each stops running readers first (ReaderGate), then takes the job lock alone.

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "ispars/service/drop_mark.hpp"
#include "ispars/service/roadmap_session.hpp"
#include "ispars/service/roadmap_store.hpp"
#include "request_input.hpp"
#include "roadmap_session_detail.hpp"

namespace ispars {

void RoadmapSession::drop() { (void)discard_store(""); }

std::filesystem::path RoadmapSession::set_aside(const std::string& why) { return discard_store(why); }

std::filesystem::path RoadmapSession::discard_store(const std::string& aside_why) {
  const char* what = aside_why.empty() ? "drop" : "set aside";
  // Running verifies stop, and new ones wait outside, so the job lock comes free at once.
  const auto readers_off = readers_->hold_off(fmt::format("scene '{}' is being dropped", name_));
  const auto job = lock_idle_job<std::unique_lock<std::shared_mutex>>(what);
  std::unique_ptr<RoadmapStore> store;
  std::uint64_t empty_generation = 0;
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    if (!recipe_ && damage_.empty())
      throw InputError(kRequest, "scene", fmt::format("scene '{}' has no roadmap", name_));
    discarding_ = true;  // no request is accepted while the store goes away
    store = std::move(store_);
    // A new generation: the empty roadmap is newer than the one discarded (replicas resync, and
    // the fleet weighs this daemon's empty scene above older copies elsewhere, also once it is
    // unloaded: the drop mark keeps the generation).
    empty_generation = std::max(session_detail::new_generation(), published_.generation + 1);
  }
  // Joining a compaction and removing files take time: not under mutex_, which every status and
  // STATS takes. The job lock (held alone) keeps jobs and readers of the builder out.
  std::filesystem::path aside;
  try {
    mark_dropped(store_dir_, empty_generation, fs_);  // first: a failure leaves the store as it was
  } catch (...) {
    std::lock_guard lock(mutex_);
    store_ = std::move(store);
    discarding_ = false;
    throw;
  }
  try {
    store.reset();
    builder_.reset();
    build_scene_.reset();
    recovered_.reset();
    if (aside_why.empty()) {
      drop_store(store_dir_, fs_);
    } else {
      aside = set_aside_store(store_dir_, aside_why, fs_);
    }
  } catch (...) {
    std::lock_guard lock(mutex_);
    discarding_ = false;
    throw;
  }
  {
    std::lock_guard lock(mutex_);
    discarding_ = false;
    damage_.clear();  // an explicit drop discards a damaged store too
    last_error_.clear();
    recipe_.reset();
    tasks_.clear();  // the tasks were the roadmap's: a drop forgets them with it
    scene_with_tasks_ = std::make_shared<const Scene>(scene_);
    samples_done_ = samples_target_ = 0;
    dense_vertices_ = dense_edges_ = 0;
    published_ = make_published(std::make_shared<const Roadmap>(scene_.pois().size()), empty_generation, 0);
    state_ = SessionState::empty;
  }
  notify_status();
  return aside;
}

void RoadmapSession::close() {
  const auto readers_off = readers_->hold_off(fmt::format("scene '{}' is being unloaded", name_));
  const auto job = lock_idle_job<std::unique_lock<std::shared_mutex>>("unload");
  std::unique_ptr<RoadmapStore> store;
  {
    std::lock_guard lock(mutex_);
    check_can_start("scene");
    closed_ = true;
    store = std::move(store_);
  }
  // The store's lock goes now, not when the last holder of this session lets go (a tour still
  // running on the published roadmap, say): the scene can be loaded again at once. Its
  // compaction is joined outside mutex_, so STATS and statuses never wait for it.
  store.reset();
  builder_.reset();
  build_scene_.reset();
}

}  // namespace ispars
