// isparsd's life and its request path: start (data directory lock, DDS, the service, stored
// roadmaps), every request through one template (header checks, the reply cache, the service),
// and an orderly stop.

#include "daemon.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstring>
#include <type_traits>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "dds_endpoints.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/wire/convert.hpp"
#include "metrics_endpoint.hpp"
#include "stop_watchdog.hpp"

namespace ispars::server {
namespace {

// Client ids are GUID strings (about 50 bytes); the IDL bound (128) is above this limit, so an
// id the transport cut is refused, never taken for another client's.
constexpr std::size_t kMaxClientId = 100;
constexpr unsigned kQuickThreads = 2;
constexpr unsigned kSlowThreads = 2;
// How often the stored copies no session holds are looked at (each read whole once per version of
// its files): damage in a standby copy is named within seconds of the daemon's start.
constexpr std::chrono::milliseconds kScrubPeriod{2000};

// Operations whose cost grows with the scene or the roadmap.
bool slow_operation(msg::Operation operation) {
  switch (operation) {
    case msg::LOAD_SCENE:
    case msg::PATH:
    case msg::SNAPSHOT:
    case msg::VERIFY:
    case msg::TASK_ADD:  // checks each POI against the surface
    case msg::TASK_LIST:
      return true;  // coverage over the roadmap
    default:
      return false;
  }
}

// A reply to `request` from `server_id`, ok until told otherwise, its body the request's operation.
template <class Request>
msg::Reply reply_to(const Request& request, const std::string& server_id) {
  msg::Reply reply;
  reply.client_id(request.client_id());
  reply.request_seq(request.request_seq());
  reply.server_id(server_id);
  reply.protocol(msg::PROTOCOL_VERSION);
  reply.ok(true);
  reply.body(wire::empty_reply_body(request.args()._d()));
  return reply;
}

}  // namespace

Daemon::Daemon(DaemonConfig config) : config_(std::move(config)), listing_(config_.scene_dir, config_.data_dir) {
  if (config_.server_id.empty()) config_.server_id = fmt::format("{}-{}", host_name(), ::getpid());
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
  ServiceSettings settings;
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
  Fleet fleet{[this] { return other_daemons(); }, [this] { return self_info(); }, [this] { announce(); }};
  fleet.taking_over = [this](const std::string& scene) { return takeovers_.running(scene); };
  claims_ = std::make_unique<SceneClaims>(config_.server_id, std::move(fleet));
  try {
    ledger_ = std::make_unique<RequestLedger>(config_.data_dir);
    open_metrics_endpoint();
    joined_ms_ = static_cast<std::uint64_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
            .count());
    dds_ = std::make_unique<DdsEndpoints>(*this, config_, joined_ms_);
    join_fleet();  // the other daemons seen, this one's id unique, claims possible
    service_ = std::make_unique<RoadmapService>(std::move(settings), service_events());
  } catch (...) {
    metrics_endpoint_.reset();  // first: its thread reads dds_
    dds_.reset();
    ::close(lock_fd_);
    throw;
  }
  try {
    announce();
    service_->load_stored_roadmaps();
    for (const std::string& name : config_.preload) {
      try {
        (void)service_->load(name);
      } catch (const std::exception& e) {
        spdlog::error("preload of scene '{}' failed: {}", name, e.what());
      }
    }
    service_->resume_pending_jobs();  // a build or extend the last run accepted and did not finish
    announce();
    quick_lane_ = std::make_unique<WorkerPool>(kQuickThreads, config_.request_queue);
    slow_lane_ = std::make_unique<WorkerPool>(kSlowThreads, config_.request_queue);
    fleet_thread_ = std::thread([this] { watch_fleet(); });
    start_serving();
  } catch (...) {
    shutdown();  // joins whatever threads were started, releases the lock
    throw;
  }
  spdlog::info(
      "isparsd {} serving on DDS domain {} (scenes from {}, data in {}, {} build workers, memory budget "
      "{:.1f} GiB, protocol {})",
      config_.server_id, config_.domain, config_.scene_dir.string(), config_.data_dir.string(), config_.workers,
      memory_budget_bytes(config_) / (1024.0 * 1024.0 * 1024.0), msg::PROTOCOL_VERSION);
}

Daemon::~Daemon() { shutdown(); }

void Daemon::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  leaving_ = true;
  serving_ = false;
  notifier_.stopping("stopping: running builds commit their current chunk");
  // Each step is named for the stop watchdog's line, should the stop hang there.
  note_stop_step("the request readers' stop");
  with_dds([](DdsEndpoints& d) { d.stop_requests(); });
  {
    std::lock_guard lock(fleet_mutex_);
    fleet_stop_ = true;
  }
  fleet_wake_.notify_all();
  note_stop_step("the fleet thread");
  if (fleet_thread_.joinable()) fleet_thread_.join();
  note_stop_step("the takeovers running");
  takeovers_.stop();
  note_stop_step("the health watchdog thread");
  if (watchdog_thread_.joinable()) watchdog_thread_.join();
  // Requests being answered finish (a running verify is stopped first, and answers so); queued
  // ones are dropped (their clients retry elsewhere or time out).
  note_stop_step("the requests being answered (quick and slow lanes)");
  if (service_) service_->stop_all_readers("the daemon is stopping");
  if (quick_lane_) quick_lane_->stop();
  if (slow_lane_) slow_lane_->stop();
  note_stop_step("the running builds' last commits and tours");
  if (service_) service_->stop();  // tours reply with their best; builds commit and stop
  note_stop_step("the metrics endpoint and the service's release");
  metrics_endpoint_.reset();  // it reads the service and the endpoints
  service_.reset();
  note_stop_step("the DDS endpoints' and participant's deletion");
  {
    std::unique_lock lock(dds_mutex_);
    dds_.reset();
  }
  note_stop_step("the data directory's lock");
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = -1;
  spdlog::info("isparsd {} stopped", config_.server_id);
}

void Daemon::receive(msg::QueryRequest request) { dispatch(std::move(request)); }
void Daemon::receive(msg::ChangeRequest request) { dispatch(std::move(request)); }

template <class Request>
void Daemon::dispatch(Request request) {
  if (!quick_lane_ || !slow_lane_) return;  // not serving yet, or stopped
  const std::string client = request.client_id().to_string();
  if (client.empty() || client.size() > kMaxClientId) {
    spdlog::warn("dropped a request with an unusable client id ({} bytes)", client.size());
    return;  // nowhere to send a reply
  }
  // Retries are settled here, before any queue: a retry of a request still waiting or running
  // takes no place in a lane, and one already answered is answered again from the cache (or,
  // for a change begun before this daemon restarted, from its ledger).
  if constexpr (std::is_same_v<Request, msg::ChangeRequest>) {
    if (auto before = ledger_->from_before(request, reply_to(request, config_.server_id))) {
      try {
        before->status(status_message(*service_->session(request.scene().to_string())));
      } catch (const std::exception&) {  // not loaded here: no status
      }
      spdlog::info("answering retry {} #{} of a change begun before this daemon started, from its ledger", client,
                   request.request_seq());
      with_dds([&](DdsEndpoints& d) { d.send_reply(*before); });
      return;
    }
  }
  msg::Reply cached;
  switch (cache_.admit(client, request.request_seq(), cached)) {
    case ReplyCache::Admission::in_progress:
      return;  // its reply is on the way
    case ReplyCache::Admission::answered:
      spdlog::debug("answering retry {} #{} from the cache", client, request.request_seq());
      with_dds([&](DdsEndpoints& d) { d.send_reply(cached); });
      return;
    case ReplyCache::Admission::new_request:
      break;
  }
  const bool slow = slow_operation(request.args()._d());
  WorkerPool& lane = slow ? *slow_lane_ : *quick_lane_;
  // A change goes ahead of the reads waiting in its lane, and a drop stops the scene's running
  // verifies now. A drop is quick work once they stop (its store goes in a rename and a removal),
  // so it takes the quick lane: in the slow one it waited for a free thread behind snapshot
  // encodings (up to 2.75 s of a 100,000-sample scene's in LoopingViewers...).
  constexpr bool change = std::is_same_v<Request, msg::ChangeRequest>;
  if constexpr (change) {
    if (request.args()._d() == msg::DROP) {
      service_->stop_readers(request.scene().to_string(),
                             fmt::format("scene '{}' is being dropped", request.scene().to_string()));
    }
  }
  const auto shared = std::make_shared<const Request>(std::move(request));
  if (!lane.submit([this, shared] { handle(*shared); }, change)) {
    cache_.forget(client, shared->request_seq());
    refuse_busy(*shared, lane, slow ? "slow" : "quick");
  }
}

template <class Request>
void Daemon::refuse_busy(const Request& request, const WorkerPool& lane, const char* lane_name) {
  spdlog::warn("{} #{} {} refused: the {} lane holds {} requests", request.client_id().to_string(),
               request.request_seq(), wire::to_string(request.args()._d()), lane_name, lane.max_queued());
  msg::Reply reply = reply_to(request, config_.server_id);
  reply.ok(false);
  reply.error(
      fmt::format("request: kind: busy: {} requests are queued on this daemon's {} lane (its limit); "
                  "retry later",
                  lane.max_queued(), lane_name));
  metrics_.count_request(wire::to_string(request.args()._d()), RequestOutcome::busy, 0.0);
  with_dds([&](DdsEndpoints& d) { d.send_reply(reply); });  // not cached: a retry is a new chance
}

template <class Request>
void Daemon::handle(const Request& request) {
  const auto taken = std::chrono::steady_clock::now();
  msg::Reply reply = reply_to(request, config_.server_id);
  const msg::Operation operation = request.args()._d();
  const std::string client = request.client_id().to_string();
  const std::string scene = request.scene().to_string();
  bool now = true;
  try {
    if (request.protocol() != msg::PROTOCOL_VERSION) {
      throw InputError("request", "protocol",
                       fmt::format("this daemon speaks ispars protocol {}, the request protocol {}; use a client "
                                   "of the same release",
                                   msg::PROTOCOL_VERSION, request.protocol()));
    }
    if (request.request_seq() == 0) {
      throw InputError("request", "request_seq", "0 is reserved (the route-open reply); start at 1");
    }
    if constexpr (std::is_same_v<Request, msg::ChangeRequest>) {
      if (RequestLedger::kept(operation)) ledger_->begin(request);  // durable before anything changes
    }
    now = answer(request, reply);
  } catch (const InputError& e) {
    reply.ok(false);
    reply.error(e.what());
    spdlog::info("{} #{} {} '{}': {}", client, request.request_seq(), wire::to_string(operation), scene.substr(0, 64),
                 e.what());
  } catch (const std::exception& e) {
    reply.ok(false);
    reply.error(std::string("internal error: ") + e.what());
    spdlog::error("{} #{} {} '{}' failed: {}", client, request.request_seq(), wire::to_string(operation),
                  scene.substr(0, 64), e.what());
  }
  if (now) finish(reply, taken);
}

void Daemon::finish(const msg::Reply& reply) {
  ledger_->answered(reply);
  cache_.complete(reply.client_id().to_string(), reply.request_seq(), reply);
  with_dds([&](DdsEndpoints& d) { d.send_reply(reply); });
}

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  return buffer;
}

}  // namespace ispars::server
