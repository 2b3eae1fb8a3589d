// The fleet member's life (join, the fleet thread, stop), its announcement, and hand-overs.

#include "ispars/server/fleet_member.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>

#include "ispars/server/dds_endpoints.hpp"
#include "ispars/server/dds_link.hpp"
#include "ispars/server/stop_signal.hpp"

namespace ispars::server {
namespace {

constexpr std::chrono::milliseconds kFleetPeriod{100};     // how often the rule is re-applied
constexpr std::chrono::seconds kReannouncePeriod{5};       // after another participant announced this id
constexpr std::chrono::seconds kListingPeriod{2};          // how often scene files and stored roadmaps are rescanned
constexpr std::chrono::seconds kSamplesAnnouncePeriod{1};  // held roadmaps' committed samples, at most this often

}  // namespace

FleetMember::FleetMember(const DaemonConfig& config, DdsLink& dds, StopSignal& stop, const std::atomic<bool>& leaving,
                         std::uint64_t joined_ms)
    : config_(config),
      dds_(dds),
      stop_(stop),
      leaving_(leaving),
      joined_ms_(joined_ms),
      listing_(config.scene_dir, config.data_dir) {
  Fleet fleet{[this] { return dds_.other_daemons(); }, [this] { return self_info(); }, [this] { announce(); }};
  fleet.taking_over = [this](const std::string& scene) { return takeovers_.running(scene); };
  claims_ = std::make_unique<SceneClaims>(config_.server_id, std::move(fleet));
}

FleetMember::~FleetMember() { stop(); }

void FleetMember::join() {
  // Announced at once (holding nothing), so that a daemon started at the same instant with the
  // same id sees this one as this one sees it. Announcements are transient-local: every live
  // daemon's reaches a new reader once discovery has matched them, which on one host takes
  // milliseconds and on a network a little more.
  announce();
  std::this_thread::sleep_for(std::chrono::milliseconds(config_.discovery_wait_ms));
  bool taken = false;
  dds_.with([&](DdsEndpoints& d) { taken = d.id_announced_elsewhere(); });
  if (taken) {
    throw ServerIdTaken(
        fmt::format("server id '{}' is already announced on DDS domain {} by another running "
                    "daemon; give each daemon its own server_id",
                    config_.server_id, config_.participant.domain));
  }
}

void FleetMember::start() {
  thread_ = std::thread([this] { watch(); });
}

void FleetMember::stop() {
  if (thread_.joinable()) thread_.join();
  takeovers_.stop();
}

void FleetMember::observe(const msg::DaemonInfo* announcement) {
  if (announcement) claims_->observe(*announcement);
  stop_.wake();
}

void FleetMember::observe(const msg::SceneStatus& status) { claims_->observe(status); }

void FleetMember::observe(const msg::SceneTask& task) { task_board_.seen(task); }

void FleetMember::claim(const std::string& scene) {
  claims_->claim(scene);
  listing_.held_again(scene);
}

void FleetMember::release(const std::string& scene) {
  claims_->release(scene);
  // A stopping daemon keeps its last announcement: it vanishes with the daemon, and the fleet
  // takes its scenes over as after a crash.
  if (!leaving_) announce();
}

void FleetMember::announce() {
  std::lock_guard lock(announce_mutex_);  // the latest state is the last written
  refresh_listing();
  const msg::DaemonInfo info = self_info();
  dds_.with([&](DdsEndpoints& d) { d.announce(info); });
}

msg::DaemonInfo FleetMember::self_info() const {
  msg::DaemonInfo info;
  info.server_id(config_.server_id);
  info.protocol(msg::PROTOCOL_VERSION);
  info.version(ISPARS_VERSION);
  info.host(host_name());
  info.pid(static_cast<std::int32_t>(::getpid()));
  info.joined_ms(joined_ms_);
  info.builder_version(kBuilderVersion);
  listing_.describe(info, service_ ? service_->held_roadmaps() : std::vector<service::ServedRoadmap>{});
  // Claimed scenes (being loaded or loaded) are announced as held: no other daemon claims them.
  for (const std::string& name : claims_->claimed()) info.loaded().push_back(name);
  return info;
}

bool FleetMember::refresh_listing() {
  if (!service_) return listing_.refresh(std::nullopt);
  return listing_.refresh(service_->loaded_scenes(),
                          [this](const std::string& scene) { return service_->scrub_problem(scene); });
}

void FleetMember::fill_gauges(DaemonGauges& g) const {
  g.fleet_tasks_known = task_board_.size();
  g.handed_over = listing_.handed_over();
  g.declined = listing_.declined_now();
  g.unservable = listing_.unservable();
}

void FleetMember::watch() {
  auto last_reannounce = std::chrono::steady_clock::now() - kReannouncePeriod;
  auto last_listing = std::chrono::steady_clock::now();
  while (stop_.wait_for(kFleetPeriod)) {
    check_namesakes(last_reannounce);
    // A scene file added or removed, or a roadmap stored, reaches the fleet within kListingPeriod.
    if (std::chrono::steady_clock::now() - last_listing >= kListingPeriod) {
      last_listing = std::chrono::steady_clock::now();
      if (refresh_listing()) announce();
    }
    dds_.rejoin_if_due();
    for (const ContestedScene& contest : claims_->contested()) {
      if (!takeovers_.running(contest.scene)) give_up(contest);  // else looked at once it ends
    }
    start_takeovers(claims_->orphans());
    merge_handed_tasks();
    announce_if_fresher();
  }
}

void FleetMember::check_namesakes(std::chrono::steady_clock::time_point& last_reannounce) {
  // At most every few seconds: two running daemons with one id would otherwise answer each
  // other's announcements without end.
  std::string older;
  bool contested = false;
  dds_.with([&](DdsEndpoints& d) {
    older = d.older_namesake();
    contested = d.take_id_contested();
  });
  if (!older.empty() && !displaced_.exchange(true)) {
    // Discovery slower than the wait at start: two daemons with one id ran. The one that joined
    // first keeps serving; this one stops as if told to.
    spdlog::error(
        "server id '{}' is also announced by a daemon that joined DDS domain {} before this one ({}); "
        "this daemon stops: give each daemon its own server_id",
        config_.server_id, config_.participant.domain, older);
    ::kill(::getpid(), SIGTERM);
  }
  if (contested && std::chrono::steady_clock::now() - last_reannounce >= kReannouncePeriod) {
    last_reannounce = std::chrono::steady_clock::now();
    spdlog::error("another participant on DDS domain {} announces this daemon's server id '{}'; announcing again",
                  config_.participant.domain, config_.server_id);
    announce();
  }
}

void FleetMember::give_up(const ContestedScene& contest) {
  std::uint64_t accepted = 0, task_events = 0;
  try {
    const service::SessionStatus st = service_->stats(contest.scene);
    accepted = std::max(st.samples_done, st.samples_target);
    task_events = st.task_events;  // with a task addition acknowledged and not committed
  } catch (const std::exception&) {
    return;  // unloaded meanwhile
  }
  // Announced with this daemon's copy from the moment the scene is released: the winner takes it
  // over, continuing to `accepted`, and no daemon weighs this copy while the winner lives.
  listing_.hand_over(
      contest.scene, {contest.winner, accepted, task_events},
      fmt::format("handed over to daemon {} ({}); this daemon's copy is kept", contest.winner, contest.why));
  spdlog::warn("scene '{}' is handed over to daemon {}: {}; the {} samples accepted here go with it", contest.scene,
               contest.winner, contest.why, accepted);
  service_->yield(contest.scene, leaving_);
}

void FleetMember::announce_if_fresher() {
  std::vector<service::ServedRoadmap> held = service_->held_roadmaps();
  const auto now = std::chrono::steady_clock::now();
  bool at_once = held.size() != last_held_.size();
  bool samples = false;
  for (std::size_t i = 0; !at_once && i < held.size(); ++i) {
    const service::ServedRoadmap& a = held[i];
    const service::ServedRoadmap& b = last_held_[i];
    at_once =
        a.scene != b.scene || a.generation != b.generation || a.target != b.target || a.task_events != b.task_events;
    samples = samples || a.samples != b.samples;
  }
  // A new roadmap or a new job is announced at once (the fleet weighs it); committed samples at
  // most once a second (each commit would otherwise be an announcement).
  if (!at_once && !(samples && now - last_held_announce_ >= kSamplesAnnouncePeriod)) return;
  last_held_ = std::move(held);
  last_held_announce_ = now;
  announce();
}

}  // namespace ispars::server
