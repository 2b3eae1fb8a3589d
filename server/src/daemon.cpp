// isparsd's life and its request path: start (data directory lock, DDS, the service, stored
// roadmaps), every request through one template (header checks, the reply cache, the service),
// and an orderly stop.

#include "daemon.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "dds_endpoints.hpp"
#include "ispars/input_error.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

// Client ids are GUID strings (about 50 bytes); the IDL bound (128) is above this limit, so an
// id the transport cut is refused, never taken for another client's.
constexpr std::size_t kMaxClientId = 100;
constexpr unsigned kRequestThreads = 4;

}  // namespace

Daemon::Daemon(DaemonConfig config) : config_(std::move(config)) {
  if (config_.server_id.empty()) config_.server_id = fmt::format("{}-{}", host_name(), ::getpid());
  std::filesystem::create_directories(config_.data_dir);
  const auto lock_path = config_.data_dir / ".isparsd.lock";
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0 || ::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    if (lock_fd_ >= 0) ::close(lock_fd_);
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
  try {
    dds_ = std::make_unique<DdsEndpoints>(*this, config_);
    service_ = std::make_unique<RoadmapService>(std::move(settings), service_events());
  } catch (...) {
    dds_.reset();
    ::close(lock_fd_);
    throw;
  }
  service_->load_stored_roadmaps();
  for (const std::string& name : config_.preload) {
    try {
      (void)service_->load(name);
    } catch (const std::exception& e) {
      spdlog::error("preload of scene '{}' failed: {}", name, e.what());
    }
  }
  announce();
  request_threads_ = std::make_unique<WorkerPool>(kRequestThreads);
  spdlog::info("isparsd {} serving on DDS domain {} (scenes from {}, data in {}, {} build workers, protocol {})",
               config_.server_id, config_.domain, config_.scene_dir.string(), config_.data_dir.string(),
               config_.workers, msg::PROTOCOL_VERSION);
}

Daemon::~Daemon() { shutdown(); }

void Daemon::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  if (dds_) dds_->stop_requests();
  if (request_threads_) request_threads_->stop();  // requests being answered finish; queued ones are dropped
  if (service_) service_->stop();                  // tours reply with their best; builds commit and stop
  service_.reset();
  dds_.reset();
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = -1;
  spdlog::info("isparsd {} stopped", config_.server_id);
}

void Daemon::receive(msg::QueryRequest request) {
  if (request_threads_) request_threads_->submit([this, request = std::move(request)] { handle(request); });
}

void Daemon::receive(msg::ChangeRequest request) {
  if (request_threads_) request_threads_->submit([this, request = std::move(request)] { handle(request); });
}

template <class Request>
void Daemon::handle(const Request& request) {
  const std::string client = request.client_id().to_string();
  if (client.empty() || client.size() > kMaxClientId) {
    spdlog::warn("dropped a request with an unusable client id ({} bytes)", client.size());
    return;  // nowhere to send a reply
  }
  msg::Reply reply;
  switch (cache_.admit(client, request.request_seq(), reply)) {
    case ReplyCache::Admission::in_progress:
      return;  // a retry of a request still running: its reply is on the way
    case ReplyCache::Admission::answered:
      spdlog::debug("answering retry {} #{} from the cache", client, request.request_seq());
      dds_->send_reply(reply);
      return;
    case ReplyCache::Admission::new_request:
      break;
  }
  const msg::Operation operation = request.args()._d();
  reply.client_id(request.client_id());
  reply.request_seq(request.request_seq());
  reply.server_id(config_.server_id);
  reply.protocol(msg::PROTOCOL_VERSION);
  reply.ok(true);
  reply.body(wire::empty_reply_body(operation));
  const std::string scene = request.scene().to_string();
  bool now = true;
  try {
    if (request.protocol() != msg::PROTOCOL_VERSION) {
      throw InputError("request", "protocol",
                       fmt::format("this daemon speaks ispars protocol {}, the request protocol {}; use a client "
                                   "of the same release",
                                   msg::PROTOCOL_VERSION, request.protocol()));
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
  if (now) finish(reply);
}

template void Daemon::handle(const msg::QueryRequest&);
template void Daemon::handle(const msg::ChangeRequest&);

void Daemon::finish(const msg::Reply& reply) {
  cache_.complete(reply.client_id().to_string(), reply.request_seq(), reply);
  if (dds_) dds_->send_reply(reply);
}

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  return buffer;
}

}  // namespace ispars::server
