// isparsd in a fleet of daemons: joining (listening for the others before claiming anything,
// refusing an id another daemon announces), then a thread that applies the ownership rule as the
// fleet changes: a scene claimed here and by a daemon that outranks this one is given up, and a
// scene whose holder left is taken over and rebuilt from its recipe (builds are deterministic).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "daemon.hpp"
#include "dds_endpoints.hpp"
#include "ispars/input_error.hpp"
#include "status_message.hpp"

namespace ispars::server {
namespace {

constexpr std::chrono::milliseconds kFleetPeriod{100};  // how often the rule is re-applied
constexpr std::chrono::seconds kReannouncePeriod{5};    // after another participant announced this id
constexpr std::chrono::seconds kListingPeriod{2};  // how often scene files and stored roadmaps are rescanned

// The samples of the roadmap `status` describes: its target while it was still building.
std::uint64_t samples_to_rebuild(const msg::SceneStatus& status) {
  const bool running = status.state() == msg::SCENE_BUILDING || status.state() == msg::SCENE_QUEUED ||
                       status.state() == msg::SCENE_REPLAYING;
  return running ? std::max(status.samples_target(), status.samples_done()) : status.samples_done();
}

}  // namespace

void Daemon::join_fleet() {
  // Announced at once (holding nothing), so that a daemon started at the same instant with the
  // same id sees this one as this one sees it. Announcements are transient-local: every live
  // daemon's reaches a new reader once discovery has matched them, which on one host takes
  // milliseconds and on a network a little more.
  announce();
  std::this_thread::sleep_for(std::chrono::milliseconds(config_.discovery_wait_ms));
  if (dds_->id_announced_elsewhere()) {
    throw ServerIdTaken(fmt::format("server id '{}' is already announced on DDS domain {} by another running "
                                         "daemon; give each daemon its own server_id",
                                         config_.server_id, config_.domain));
  }
}

void Daemon::fleet_changed() { fleet_wake_.notify_all(); }

void Daemon::status_seen(const msg::SceneStatus& status) {
  if (claims_) claims_->observe(status);
}

void Daemon::watch_fleet() {
  auto last_reannounce = std::chrono::steady_clock::now() - kReannouncePeriod;
  auto last_listing = std::chrono::steady_clock::now();
  std::unique_lock lock(fleet_mutex_);
  while (!fleet_stop_) {
    fleet_wake_.wait_for(lock, kFleetPeriod);
    if (fleet_stop_) break;
    lock.unlock();
    // At most every few seconds: two running daemons with one id would otherwise answer each
    // other's announcements without end.
    if (const std::string older = dds_->older_namesake(); !older.empty() && !displaced_.exchange(true)) {
      // Discovery slower than the wait at start: two daemons with one id ran. The one that
      // joined first keeps serving; this one stops as if told to.
      spdlog::error("server id '{}' is also announced by a daemon that joined DDS domain {} before this one ({}); "
                    "this daemon stops: give each daemon its own server_id",
                    config_.server_id, config_.domain, older);
      ::kill(::getpid(), SIGTERM);
    }
    if (dds_->take_id_contested() && std::chrono::steady_clock::now() - last_reannounce >= kReannouncePeriod) {
      last_reannounce = std::chrono::steady_clock::now();
      spdlog::error("another participant on DDS domain {} announces this daemon's server id '{}'; announcing again",
                    config_.domain, config_.server_id);
      announce();
    }
    // A scene file added or removed, or a roadmap stored, reaches the fleet within kListingPeriod.
    if (std::chrono::steady_clock::now() - last_listing >= kListingPeriod) {
      last_listing = std::chrono::steady_clock::now();
      if (refresh_listing()) announce();
    }
    for (const std::string& scene : claims_->contested()) {
      spdlog::warn("scene '{}' is also claimed by a daemon that outranks {} under the fleet's rule; giving it up",
                   scene, config_.server_id);
      service_->yield(scene, leaving_);
    }
    for (const OrphanScene& orphan : claims_->orphans()) take_over(orphan);
    lock.lock();
  }
}

void Daemon::take_over(const OrphanScene& orphan) {
  spdlog::warn("daemon {} left while holding scene '{}'; this daemon takes it over", orphan.former_owner,
               orphan.scene);
  try {
    const auto [session, loaded_now] = service_->load(orphan.scene);
    const auto recipe = orphan.last_status ? recipe_of(*orphan.last_status) : std::nullopt;
    const std::uint64_t samples = orphan.last_status ? samples_to_rebuild(*orphan.last_status) : 0;
    if (!recipe || samples == 0) return;  // it held no roadmap, or a damaged one: loaded as it is here
    BuildRequest request = rebuild_request(*recipe, samples);
    const SessionStatus mine = session->status();
    if (mine.recipe && same_roadmap(*mine.recipe, *recipe) && mine.samples_done <= request.samples) {
      if (mine.samples_done < request.samples) service_->extend(orphan.scene, request.samples - mine.samples_done);
    } else {
      request.replace = mine.recipe.has_value();
      service_->build(orphan.scene, request);
    }
    spdlog::info("scene '{}' taken over from {}: rebuilding its {} roadmap (seed {}) to {} samples", orphan.scene,
                 orphan.former_owner, orphan.last_status->method().to_string(), request.seed, request.samples);
  } catch (const std::exception& e) {
    spdlog::error("taking over scene '{}' from {} failed: {}", orphan.scene, orphan.former_owner, e.what());
  }
}

}  // namespace ispars::server
