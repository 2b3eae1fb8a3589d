// isparsd's life: start (data directory lock, DDS, the fleet, the service, stored roadmaps), the
// service's events wired to the parts that publish them, and an orderly stop.

#include "ispars/server/daemon.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "ispars/ros2/ros2_mirror.hpp"
#include "ispars/server/dds_endpoints.hpp"
#include "ispars/server/stop_watchdog.hpp"

namespace ispars::server {
namespace {

// How often the stored copies no session holds are looked at (each read whole once per version of
// its files): damage in a standby copy is named within seconds of the daemon's start.
constexpr std::chrono::milliseconds kScrubPeriod{2000};

DaemonConfig with_server_id(DaemonConfig config) {
  if (config.server_id.empty()) config.server_id = fmt::format("{}-{}", host_name(), ::getpid());
  return config;
}

std::uint64_t now_ms() {
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
          .count());
}

}  // namespace

Daemon::Daemon(DaemonConfig config)
    : config_(with_server_id(std::move(config))),
      joined_ms_(now_ms()),
      dds_(
          config_, [this] { return std::make_unique<DdsEndpoints>(*this, config_, joined_ms_); }, stop_),
      statuses_(config_.server_id, dds_, metrics_, leaving_),
      fleet_(config_, dds_, stop_, leaving_, joined_ms_),
      operator_(config_, metrics_, dds_, stop_, leaving_, [this](DaemonGauges& g) { fleet_.fill_gauges(g); }) {
  lock_data_dir();
  std::unique_ptr<RequestLedger> ledger;
  try {
    ledger = std::make_unique<RequestLedger>(config_.data_dir);
    operator_.open_metrics();  // first of all: a port in use stops the start
    dds_.open();
    fleet_.join();  // the other daemons seen, this one's id unique, claims possible
    open_ros2();
    service_ = std::make_unique<service::RoadmapService>(service_settings(), service_events());
    fleet_.attach(service_.get());
  } catch (...) {
    operator_.close_metrics();  // first: its thread reads the DDS link
    ros2_.reset();
    dds_.close();
    ::close(lock_fd_);
    throw;
  }
  try {
    serve(std::move(ledger));
  } catch (...) {
    shutdown();  // joins whatever threads were started, releases the lock
    throw;
  }
  spdlog::info(
      "isparsd {} serving on DDS domain {} (scenes from {}, data in {}, {} build workers, memory budget "
      "{:.1f} GiB, protocol {})",
      config_.server_id, config_.participant.domain, config_.scene_dir.string(), config_.data_dir.string(),
      config_.workers, memory_budget_bytes(config_) / (1024.0 * 1024.0 * 1024.0), msg::PROTOCOL_VERSION);
}

Daemon::~Daemon() { shutdown(); }

void Daemon::lock_data_dir() {
  std::filesystem::create_directories(config_.data_dir);
  const auto lock_path = config_.data_dir / ".isparsd.lock";
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0) {
    // A read-only or foreign data directory: every commit would fail, so the daemon does not start.
    throw std::runtime_error(fmt::format("data directory {} is not writable ({}: {})", config_.data_dir.string(),
                                         lock_path.filename().string(), std::strerror(errno)));
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    throw std::runtime_error("data directory " + config_.data_dir.string() + " is in use by another isparsd");
  }
}

void Daemon::serve(std::unique_ptr<RequestLedger> ledger) {
  fleet_.announce();
  service_->load_stored_roadmaps();
  for (const std::string& name : config_.preload) {
    try {
      (void)service_->load(name);
    } catch (const std::exception& e) {
      spdlog::error("preload of scene '{}' failed: {}", name, e.what());
    }
  }
  service_->resume_pending_jobs();  // a build or extend the last run accepted and did not finish
  fleet_.announce();
  router_ = std::make_unique<RequestRouter>(
      RequestRouter::Parts{config_.server_id, config_.request_queue, *service_, statuses_, dds_, metrics_,
                           fleet_.gate(), [this](const std::string& scene) { return fleet_.note(scene); }},
      std::move(ledger));
  {
    std::unique_lock lock(receiving_);
    serving_ = router_.get();
  }
  dds_.set_hooks({[this] { fleet_.announce(); }, [this] { republish(); }});
  fleet_.start();
  operator_.start_serving(router_->quick_lane(), [this](DaemonGauges& g) { fill_service_gauges(g); });
}

void Daemon::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  leaving_ = true;
  operator_.stopping("stopping: running builds commit their current chunk");
  // Each step is named for the stop watchdog's line, should the stop hang there.
  note_stop_step("the request readers' stop");
  dds_.with([](DdsEndpoints& d) { d.stop_requests(); });
  {
    // Waits for the DDS callbacks inside receive(): none reaches the router or the service later.
    std::unique_lock lock(receiving_);
    serving_ = nullptr;
  }
  stop_.stop();
  note_stop_step("the fleet thread and the takeovers running");
  fleet_.stop();
  note_stop_step("the health watchdog thread");
  operator_.stop();
  // Requests being answered finish (a running verify is stopped first, and answers so); queued
  // ones are dropped (their clients retry elsewhere or time out).
  note_stop_step("the requests being answered (quick and slow lanes)");
  if (service_) service_->stop_all_readers("the daemon is stopping");
  if (router_) router_->stop();
  note_stop_step("the running builds' last commits and tours");
  if (service_) service_->stop();  // tours reply with their best; builds commit and stop
  note_stop_step("the ROS 2 mirror's thread");
  if (ros2_) ros2_->stop();  // it reads the service; later marks are dropped
  note_stop_step("the metrics endpoint and the service's release");
  operator_.close_metrics();  // it reads the service and the endpoints
  fleet_.attach(nullptr);
  service_.reset();
  note_stop_step("the DDS endpoints' and participant's deletion");
  dds_.close();
  router_.reset();
  ros2_.reset();
  note_stop_step("the data directory's lock");
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = -1;
  spdlog::info("isparsd {} stopped", config_.server_id);
}

void Daemon::receive(msg::QueryRequest request) {
  std::shared_lock lock(receiving_);
  if (serving_) serving_->receive(std::move(request));
}

void Daemon::receive(msg::ChangeRequest request) {
  std::shared_lock lock(receiving_);
  if (serving_) serving_->receive(std::move(request));
}

service::ServiceSettings Daemon::service_settings() const {
  service::ServiceSettings settings;
  settings.server_id = config_.server_id;
  settings.scene_dir = config_.scene_dir;
  settings.data_dir = config_.data_dir;
  settings.limits.max_samples = config_.max_samples;
  settings.limits.compact_every = config_.snapshot_compact_every;
  settings.limits.build_threads = config_.build_threads;
  settings.build_workers = config_.workers;
  settings.tour_workers = config_.workers;
  settings.memory_budget_bytes = memory_budget_bytes(config_);
  settings.scrub_period = kScrubPeriod;
  return settings;
}

service::ServiceEvents Daemon::service_events() {
  service::ServiceEvents events;
  events.on_commit = [this](const std::string& scene, const RoadmapBatch& batch, std::uint64_t generation,
                            std::uint64_t samples, std::size_t poi_count) {
    statuses_.publish_commit(scene, batch, generation, samples, poi_count);
    if (ros2_) ros2_->roadmap_changed(scene);
  };
  events.on_status = [this](const service::RoadmapSession& session) {
    statuses_.publish_status(session);
    if (ros2_) ros2_->roadmap_changed(session.name());  // a load, a drop: drawn if it changed
  };
  events.on_unloaded = [this](const std::string& scene, bool given_up) {
    statuses_.publish_unloaded(scene, given_up);
    if (ros2_) ros2_->scene_gone(scene);
  };
  events.on_tour = [this](const std::string& scene, const service::TourOutcome& outcome) {
    if (ros2_ && !outcome.flown_path.empty()) ros2_->tour_flown(scene, outcome.flown_path);
  };
  events.on_scenes_changed = [this] { fleet_.announce(); };
  events.claim = [this](const std::string& scene) { fleet_.claim(scene); };
  events.release = [this](const std::string& scene) { fleet_.release(scene); };
  return events;
}

void Daemon::open_ros2() {
  if (!config_.ros2) return;
  ros2::Ros2MirrorOptions options;
  options.participant = config_.participant;
  options.frame = config_.ros2_frame;
  ros2_ = std::make_unique<ros2::Ros2Mirror>(options, [this](const std::string& scene) {
    std::optional<ros2::MirroredRoadmap> drawn;
    try {
      const auto session = service_->session(scene);
      drawn = ros2::MirroredRoadmap{session->published().roadmap, session->scene_with_tasks()->pois()};
    } catch (const std::exception&) {
      // not loaded (any more)
    }
    return drawn;
  });
}

void Daemon::republish() {
  for (const std::string& scene : service_->loaded_scenes()) {
    try {
      statuses_.republish(scene, *service_->session(scene));
    } catch (const std::exception&) {
      // unloaded meanwhile
    }
  }
}

void Daemon::fill_service_gauges(DaemonGauges& g) const {
  for (const std::string& scene : service_->loaded_scenes()) {
    try {
      const service::SessionStatus s = service_->stats(scene);
      g.scenes.push_back(
          {scene, std::string(to_string(s.state)), s.samples_done, s.vertices, s.edges, s.poi_count, s.pois_covered});
    } catch (const std::exception&) {
      // unloaded since it was listed
    }
  }
  g.memory_reserved_bytes = service_->budget().reserved();
  g.memory_leased_bytes = service_->budget().leased();
}

}  // namespace ispars::server
