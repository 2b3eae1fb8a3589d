#include "daemon.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "dds_endpoints.hpp"
#include "ispars/input_error.hpp"
#include "ispars/service/scene_catalog.hpp"
#include "ispars/wire/convert.hpp"
#include "status_message.hpp"

namespace ispars::server {
namespace {

constexpr std::size_t kMaxText = 256;        // client id, scene, method
constexpr std::size_t kMaxOverrides = 16;
constexpr unsigned kRequestThreads = 4;
// Tours admitted (queued or running) per tour worker; past that a TOUR request gets "busy".
constexpr std::size_t kToursPerWorker = 2;


void check_text(const std::string& value, const char* field, std::size_t limit) {
  if (value.size() > limit) {
    throw InputError("request", field, fmt::format("is {} bytes long; at most {} allowed", value.size(), limit));
  }
}

}  // namespace

Daemon::Daemon(DaemonConfig config) : config_(std::move(config)) {
  if (config_.server_id.empty()) config_.server_id = fmt::format("{}-{}", host_name(), ::getpid());
  std::filesystem::create_directories(config_.data_dir);
  const auto lock_path = config_.data_dir / ".isparsd.lock";
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock_fd_ < 0 || ::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    throw std::runtime_error("data directory " + config_.data_dir.string() + " is in use by another isparsd");
  }
  if (!std::filesystem::is_directory(config_.scene_dir)) {
    throw std::runtime_error("scene directory " + config_.scene_dir.string() + " does not exist");
  }
  remove_dropped_stores(config_.data_dir);
  workers_ = std::make_unique<WorkerPool>(config_.workers);
  tour_workers_ = std::make_unique<WorkerPool>(config_.workers);
  dds_ = std::make_unique<DdsEndpoints>(*this, config_);
  recover_stored_roadmaps();
  for (const std::string& name : config_.preload) {
    try {
      if (!session_or_null(name)) open_session(name);
    } catch (const std::exception& e) {
      spdlog::error("preload of scene '{}' failed: {}", name, e.what());
    }
  }
  announce();
  for (unsigned i = 0; i < kRequestThreads; ++i) request_threads_.emplace_back([this] { serve_requests(); });
  spdlog::info("isparsd {} serving on DDS domain {} (scenes from {}, data in {}, {} build workers)", config_.server_id,
               config_.domain, config_.scene_dir.string(), config_.data_dir.string(), config_.workers);
}

Daemon::~Daemon() { shutdown(); }

void Daemon::shutdown() {
  if (shut_down_) return;
  shut_down_ = true;
  stopping_ = true;
  stop_tours("");
  if (dds_) dds_->stop_requests();
  queue_wake_.notify_all();
  for (auto& t : request_threads_) t.join();
  request_threads_.clear();
  workers_->stop();       // running builds commit their current chunk and return
  tour_workers_->stop();  // running tours stop early and reply with their best
  std::vector<std::shared_ptr<RoadmapSession>> sessions;
  {
    std::lock_guard lock(sessions_mutex_);
    for (const auto& [name, s] : sessions_) sessions.push_back(s);
  }
  for (const auto& s : sessions) publish_unloaded(s->name());
  dds_.reset();
  if (lock_fd_ >= 0) ::close(lock_fd_);
  lock_fd_ = -1;
  spdlog::info("isparsd {} stopped", config_.server_id);
}

void Daemon::enqueue(msg::Request request) {
  {
    std::lock_guard lock(queue_mutex_);
    queue_.push_back(std::move(request));
  }
  queue_wake_.notify_one();
}

void Daemon::serve_requests() {
  for (;;) {
    msg::Request request;
    {
      std::unique_lock lock(queue_mutex_);
      queue_wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      request = std::move(queue_.front());
      queue_.pop_front();
    }
    handle(request);
  }
}

void Daemon::handle(const msg::Request& request) {
  msg::Reply reply;
  if (request.client_id().empty() || request.client_id().size() > kMaxText) {
    spdlog::warn("dropped a request with an unusable client id ({} bytes)", request.client_id().size());
    return;  // nowhere to send a reply
  }
  switch (cache_.admit(request.client_id(), request.request_seq(), reply)) {
    case ReplyCache::Admission::in_progress:
      return;  // a retry of a request still running: its reply is on the way
    case ReplyCache::Admission::answered:
      spdlog::debug("answering retry {} #{} from the cache", request.client_id(), request.request_seq());
      dds_->send_reply(reply);
      return;
    case ReplyCache::Admission::new_request:
      break;
  }
  if (request.kind() == msg::TOUR) {
    // A tour searches for its whole budget: run it on a tour worker, reply when it ends. At most
    // kToursPerWorker per worker wait or run; past that the request is refused, not queued.
    const std::size_t limit = kToursPerWorker * std::max(1u, config_.workers);
    bool admitted = false;
    {
      std::lock_guard lock(tours_mutex_);
      if (tours_admitted_ < limit) {
        ++tours_admitted_;
        admitted = true;
      }
    }
    if (!admitted) {
      reply.client_id(request.client_id());
      reply.request_seq(request.request_seq());
      reply.server_id(config_.server_id);
      reply.kind(request.kind());
      reply.ok(false);
      reply.error(fmt::format("request: kind: busy: {} tours are queued or running (this daemon's limit); retry later",
                              limit));
      cache_.complete(request.client_id(), request.request_seq(), reply);
      dds_->send_reply(reply);
      return;
    }
    tour_workers_->submit([this, request] {
      msg::Reply r = answer(request);
      {
        std::lock_guard lock(tours_mutex_);
        --tours_admitted_;
      }
      cache_.complete(request.client_id(), request.request_seq(), r);
      if (dds_) dds_->send_reply(r);
    });
    return;
  }
  reply = answer(request);
  cache_.complete(request.client_id(), request.request_seq(), reply);
  dds_->send_reply(reply);
}

void Daemon::check_request(const msg::Request& r) const {
  check_text(r.scene(), "scene", kMaxText);
  check_text(r.method(), "method", 32);
  if (r.overrides().size() > kMaxOverrides) {
    throw InputError("request", "overrides", fmt::format("{} given; at most {} allowed", r.overrides().size(), kMaxOverrides));
  }
  for (const auto& o : r.overrides()) check_text(o.name(), "overrides.name", 64);
}

msg::Reply Daemon::answer(const msg::Request& request) {
  msg::Reply reply;
  reply.client_id(request.client_id());
  reply.request_seq(request.request_seq());
  reply.server_id(config_.server_id);
  reply.kind(request.kind());
  reply.ok(true);
  const std::string& name = request.scene();
  try {
    check_request(request);
    switch (request.kind()) {
      case msg::LIST_SCENES: list_scenes(reply); break;
      case msg::LOAD_SCENE: load_scene(name, reply); break;
      case msg::UNLOAD_SCENE: unload_scene(name, reply); break;
      case msg::BUILD: build(request, reply); break;
      case msg::EXTEND: extend(request, reply); break;
      case msg::CANCEL: {
        const auto s = session(name);
        const bool build = s->cancel();
        const std::size_t tours = stop_tours(name);
        reply.message(fmt::format("{}; {} tour{} stopped (each replies with its best tour so far)",
                                  build ? "cancelling the build after the current chunk" : "no build running", tours,
                                  tours == 1 ? "" : "s"));
        reply.status(status_message(*s));
        break;
      }
      case msg::STATS: reply.status(status_message(*session(name))); break;
      case msg::PATH: {
        const auto s = session(name);
        const RoadmapPath path = s->path(wire::from_message(request.from()), wire::from_message(request.to()));
        for (const Vec3& p : path.waypoints) reply.waypoints().push_back(wire::to_message(p));
        reply.length(path.length);
        reply.status(status_message(*s));
        break;
      }
      case msg::SNAPSHOT: snapshot(request, reply); break;
      case msg::TOUR: tour(request, reply); break;
      case msg::DROP: {
        const auto s = session(name);
        s->drop();
        reply.message(fmt::format("dropped the roadmap of '{}'", name));
        reply.status(status_message(*s));
        break;
      }
      case msg::VERIFY: {
        const auto s = session(name);
        const VerificationReport r = s->verify();
        // Invariant 1 is Inspection-SPARS's promise; SPARS and the others do not make it.
        const auto recipe = s->status().recipe;
        const bool promises_invariant = recipe && recipe->method == BuildMethod::ispars;
        reply.violations(r.invalid_vertices + r.invalid_edges + r.wrong_costs + r.sparse_not_dense +
                         (promises_invariant ? r.invariant_violations : 0));
        reply.message(fmt::format("invalid vertices {}, invalid edges {}, wrong costs {}, sparse not dense {}, "
                                  "Invariant 1 violations {} at {} dense vertices{}",
                                  r.invalid_vertices, r.invalid_edges, r.wrong_costs, r.sparse_not_dense,
                                  r.invariant_violations, r.invariant_vertices,
                                  promises_invariant ? "" : " (not promised by this method)"));
        reply.status(status_message(*s));
        break;
      }
      default:
        throw InputError("request", "kind", fmt::format("unknown request kind {}", static_cast<int>(request.kind())));
    }
  } catch (const InputError& e) {
    reply.ok(false);
    reply.error(e.what());
    spdlog::info("{} #{} {} '{}': {}", request.client_id(), request.request_seq(), wire::to_string(request.kind()),
                 name.substr(0, 64), e.what());
  } catch (const std::exception& e) {
    reply.ok(false);
    reply.error(std::string("internal error: ") + e.what());
    spdlog::error("{} #{} {} '{}' failed: {}", request.client_id(), request.request_seq(),
                  wire::to_string(request.kind()), name.substr(0, 64), e.what());
  }
  return reply;
}

void Daemon::list_scenes(msg::Reply& reply) const {
  std::lock_guard lock(sessions_mutex_);
  for (const std::string& name : list_scene_names(config_.scene_dir)) {
    msg::SceneEntry e;
    e.name(name);
    e.server_id(config_.server_id);
    if (const auto it = sessions_.find(name); it != sessions_.end()) {
      e.loaded(true);
      e.has_roadmap(it->second->status().recipe.has_value());
    } else {
      e.has_roadmap(std::filesystem::exists(config_.data_dir / name / "recipe.json"));
    }
    reply.scenes().push_back(e);
  }
}

std::shared_ptr<RoadmapSession> Daemon::session_or_null(const std::string& name) const {
  std::lock_guard lock(sessions_mutex_);
  const auto it = sessions_.find(name);
  return it == sessions_.end() ? nullptr : it->second;
}

std::shared_ptr<RoadmapSession> Daemon::session(const std::string& name) const {
  if (auto s = session_or_null(name)) return s;
  if (!valid_scene_name(name)) (void)scene_file(config_.scene_dir, name);  // names the bad name
  throw InputError("request", "scene", fmt::format("scene '{}' is not loaded on daemon {}", name, config_.server_id));
}

std::shared_ptr<RoadmapSession> Daemon::open_session(const std::string& name) {
  const std::filesystem::path file = scene_file(config_.scene_dir, name);
  // Reserve the name: two concurrent loads must not both open the scene's store.
  {
    std::lock_guard lock(sessions_mutex_);
    if (sessions_.count(name) || !loading_.insert(name).second) {
      throw InputError("request", "scene", fmt::format("scene '{}' is already loaded or being loaded", name));
    }
  }
  struct Unreserve {
    Daemon& d;
    const std::string& n;
    ~Unreserve() {
      std::lock_guard lock(d.sessions_mutex_);
      d.loading_.erase(n);
    }
  } unreserve{*this, name};
  if (const auto other = dds_->status_of(name);
      other && other->server_id() != config_.server_id && other->state() != msg::SCENE_UNLOADED) {
    throw InputError("request", "scene", fmt::format("scene '{}' is owned by daemon {}", name, other->server_id()));
  }
  Scene scene = Scene::load(file);
  SessionCallbacks callbacks;
  callbacks.on_commit = [this, name](const RoadmapBatch& batch, std::uint64_t generation, std::uint64_t samples) {
    dds_->publish_update(wire::to_message(batch, name, config_.server_id, generation, samples));
  };
  callbacks.on_status = [this](const SessionStatus& status) { publish_status(status.scene); };
  SessionLimits limits;
  limits.max_samples = config_.max_samples;
  limits.compact_every = config_.snapshot_compact_every;
  limits.build_threads = config_.build_threads;
  auto session = std::make_shared<RoadmapSession>(name, std::move(scene), config_.data_dir / name, limits,
                                                  std::move(callbacks));
  {
    std::lock_guard lock(sessions_mutex_);
    sessions_.emplace(name, session);
  }
  if (!session->recovery_note().empty()) spdlog::info("scene '{}': {}", name, session->recovery_note());
  spdlog::info("loaded scene '{}' ({} triangles, {} POIs)", name, session->scene().mesh().triangle_count(),
               session->scene().pois().size());
  publish_status(name);
  announce();
  return session;
}

void Daemon::load_scene(const std::string& name, msg::Reply& reply) {
  if (const auto s = session_or_null(name)) {
    reply.message(fmt::format("scene '{}' was already loaded", name));
    reply.status(status_message(*s));
    return;
  }
  const auto s = open_session(name);
  reply.message(s->recovery_note().empty() ? fmt::format("loaded scene '{}'", name) : s->recovery_note());
  reply.status(status_message(*s));
}

void Daemon::unload_scene(const std::string& name, msg::Reply& reply) {
  const auto s = session(name);
  if (s->busy()) throw InputError("request", "scene", fmt::format("a build is running on scene '{}'; cancel it first", name));
  s->close();  // atomically with the busy check inside: no job can start on it any more
  {
    std::lock_guard lock(sessions_mutex_);
    sessions_.erase(name);
  }
  publish_unloaded(name);
  announce();
  reply.message(fmt::format("unloaded scene '{}' (its stored roadmap stays on disk)", name));
}

void Daemon::build(const msg::Request& request, msg::Reply& reply) {
  const auto s = session(request.scene());
  const auto method = parse_build_method(request.method());
  if (!method) {
    throw InputError("request", "method",
                     fmt::format("'{}' is not one of {}", request.method().substr(0, 32), build_method_names()));
  }
  // A bounded IDL string (string<16>): the transport refuses longer ones.
  const std::string variant_name = request.variant().c_str();
  const auto variant = variant_name.empty() ? SparsVariant::stretch : parse_spars_variant(variant_name);
  if (!variant) {
    throw InputError("request", "variant", fmt::format("'{}' is not one of {}", variant_name, spars_variant_names()));
  }
  if (request.samples() == 0) throw InputError("request", "samples", "must be at least 1");
  BuildRequest build;
  build.method = *method;
  build.variant = *variant;
  build.samples = request.samples();
  build.seed = request.seed();
  build.replace = request.replace();
  for (const auto& o : request.overrides()) {
    if (!build.overrides.emplace(o.name(), o.value()).second) {
      throw InputError("request", "overrides." + o.name(), "given twice");
    }
  }
  s->request_build(build);
  schedule(s);
  reply.message(fmt::format("building {} on '{}': {} samples, seed {}", request.method(), request.scene(),
                            request.samples(), request.seed()));
  reply.status(status_message(*s));
}

void Daemon::extend(const msg::Request& request, msg::Reply& reply) {
  const auto s = session(request.scene());
  s->request_extend(request.samples());
  schedule(s);
  reply.message(fmt::format("extending '{}' by {} samples", request.scene(), request.samples()));
  reply.status(status_message(*s));
}

void Daemon::schedule(const std::shared_ptr<RoadmapSession>& session) {
  workers_->submit([this, session] {
    spdlog::info("scene '{}': job started", session->name());
    session->run_job(stopping_);
    const SessionStatus st = session->status();
    if (st.state == SessionState::failed) {
      spdlog::error("scene '{}': job failed: {}", session->name(), st.last_error);
    } else {
      spdlog::info("scene '{}': job ended at {} samples, {} vertices, {} edges{}", session->name(), st.samples_done,
                   st.vertices, st.edges, st.last_error.empty() ? "" : " (" + st.last_error + ")");
    }
  });
}

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  return buffer;
}

void Daemon::recover_stored_roadmaps() {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(config_.data_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_directory() || !valid_scene_name(name)) continue;
    if (!std::filesystem::exists(entry.path() / "recipe.json")) continue;
    try {
      open_session(name);
    } catch (const std::exception& e) {
      spdlog::error("stored roadmap of scene '{}' not reloaded: {}", name, e.what());
    }
  }
}

}  // namespace ispars::server
