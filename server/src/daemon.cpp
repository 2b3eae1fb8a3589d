#include "daemon.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "dds_endpoints.hpp"
#include "ispars/gip_solver.hpp"
#include "ispars/inspection_graph.hpp"
#include "ispars/input_error.hpp"
#include "ispars/service/scene_catalog.hpp"
#include "ispars/wire/convert.hpp"
#include "status_message.hpp"

namespace ispars::server {
namespace {

constexpr std::size_t kMaxText = 256;        // client id, scene, method
constexpr std::size_t kMaxOverrides = 16;
constexpr std::size_t kSnapshotChunk = 1024 * 1024;
constexpr std::size_t kSnapshotsKept = 4;
constexpr unsigned kRequestThreads = 4;
// Tours admitted (queued or running) per tour worker; past that a TOUR request gets "busy".
constexpr std::size_t kToursPerWorker = 2;

std::string host_name() {
  char buffer[256] = {};
  if (::gethostname(buffer, sizeof(buffer) - 1) != 0) return "host";
  return buffer;
}

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
    throw InputError("request", "method", fmt::format("'{}' is not one of dense, spars, ispars, irisc",
                                                      request.method().substr(0, 32)));
  }
  if (request.samples() == 0) throw InputError("request", "samples", "must be at least 1");
  BuildRequest build;
  build.method = *method;
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

void Daemon::snapshot(const msg::Request& request, msg::Reply& reply) {
  const auto s = session(request.scene());
  std::shared_ptr<const std::string> bytes;
  std::uint64_t generation = request.snapshot_generation();
  std::uint64_t version = request.snapshot_version();
  {
    std::lock_guard lock(snapshots_mutex_);
    for (const auto& e : snapshots_) {
      if (version != 0 && e.scene == s->name() && e.generation == generation && e.version == version) bytes = e.bytes;
    }
  }
  if (!bytes) {
    const PublishedRoadmap published = s->published();
    if (version == 0) {
      generation = published.generation;
      version = published.roadmap->version();
    } else if (published.generation != generation || published.roadmap->version() < version) {
      throw InputError("request", "snapshot_version",
                       fmt::format("version {} of roadmap generation {} is no longer available; start the snapshot again",
                                   version, generation));
    }
    bytes = std::make_shared<const std::string>(encode_batch(batch_range(*published.roadmap, 0, version)));
    std::lock_guard lock(snapshots_mutex_);
    snapshots_.push_back({s->name(), generation, version, bytes});
    if (snapshots_.size() > kSnapshotsKept) snapshots_.pop_front();
  }
  const std::size_t count = std::max<std::size_t>(1, (bytes->size() + kSnapshotChunk - 1) / kSnapshotChunk);
  if (request.chunk_index() >= count) {
    throw InputError("request", "chunk_index", fmt::format("{} is past the last chunk ({})", request.chunk_index(), count - 1));
  }
  const std::size_t begin = request.chunk_index() * kSnapshotChunk;
  const std::size_t end = std::min(bytes->size(), begin + kSnapshotChunk);
  reply.snapshot_generation(generation);
  reply.snapshot_version(version);
  reply.chunk_index(request.chunk_index());
  reply.chunk_count(static_cast<std::uint32_t>(count));
  if (request.chunk_index() == 0) {
    reply.status(status_message(*s));
    reply.root(wire::to_message(s->scene().config().root));
    for (const Vec3& p : s->scene().pois()) reply.pois().push_back(wire::to_message(p));
  }
  reply.chunk().assign(bytes->begin() + static_cast<std::ptrdiff_t>(begin), bytes->begin() + static_cast<std::ptrdiff_t>(end));
}

void Daemon::tour(const msg::Request& request, msg::Reply& reply) {
  const auto s = session(request.scene());
  if (!std::isfinite(request.budget()) || !(request.budget() > 0.0) || request.budget() > 3600.0) {
    throw InputError("request", "budget", fmt::format("must be in (0, 3600] seconds, got {}", request.budget()));
  }
  if (request.targets().size() > 1'000'000) throw InputError("request", "targets", "more than 1000000 given");
  const PublishedRoadmap published = s->published();
  if (!s->status().recipe || published.roadmap->vertex_count() == 0) {
    throw InputError("request", "scene", fmt::format("scene '{}' has no roadmap yet", request.scene()));
  }
  // This tour's stop flag: set by CANCEL on the scene and at shutdown.
  const auto stop = std::make_shared<std::atomic<bool>>(stopping_.load());
  std::multimap<std::string, std::shared_ptr<std::atomic<bool>>>::iterator registered;
  {
    std::lock_guard lock(tours_mutex_);
    registered = running_tours_.emplace(request.scene(), stop);
  }
  struct Unregister {
    Daemon* daemon;
    std::multimap<std::string, std::shared_ptr<std::atomic<bool>>>::iterator it;
    ~Unregister() {
      std::lock_guard lock(daemon->tours_mutex_);
      daemon->running_tours_.erase(it);
    }
  } unregister{this, registered};
  if (stopping_) stop->store(true);  // shutdown began before the registration
  const InspectionGraph graph = InspectionGraph::from_roadmap(*published.roadmap);
  GipOptions options;
  options.budget_seconds = request.budget();
  options.seed = request.seed();
  options.stop = stop.get();
  if (!request.targets().empty()) options.targets = std::vector<PoiId>(request.targets().begin(), request.targets().end());
  // Progress carries the best tour and the best bound so far; the two callbacks come from
  // different threads.
  std::mutex progress_mutex;
  double best_cost = 0.0, best_bound = 0.0;
  const auto publish = [&](double seconds) {
    msg::TourProgress progress;
    progress.client_id(request.client_id());
    progress.request_seq(request.request_seq());
    progress.scene(request.scene());
    progress.seconds(seconds);
    progress.cost(best_cost);
    progress.lower_bound(best_bound);
    dds_->publish_tour_progress(progress);
  };
  options.on_improvement = [&](double seconds, double cost) {
    std::lock_guard lock(progress_mutex);
    best_cost = cost;
    publish(seconds);
  };
  options.on_bound = [&](double seconds, double bound) {
    std::lock_guard lock(progress_mutex);
    best_bound = bound;
    publish(seconds);
  };
  const GipResult r = solve_gip(graph, options);
  reply.walk(std::vector<std::uint32_t>(r.tour.walk.begin(), r.tour.walk.end()));
  for (const VertexId v : r.tour.walk) reply.waypoints().push_back(wire::to_message(published.roadmap->position(v)));
  reply.length(r.tour.cost);
  reply.covered(static_cast<std::uint32_t>(r.tour.covered.size()));
  reply.target_count(static_cast<std::uint32_t>(r.targets.size()));
  reply.lower_bound(r.lower_bound.value_or(0.0));
  reply.tour_valid(r.validation.valid());
  for (const auto& [t, c] : r.trace) {
    reply.trace().push_back(t);
    reply.trace().push_back(c);
  }
  for (const auto& [t, b] : r.bound_trace) {
    reply.bound_trace().push_back(t);
    reply.bound_trace().push_back(b);
  }
  reply.bound_complete(r.bound_complete);
  reply.tour_version(published.roadmap->version());
  reply.message(fmt::format("tour of cost {:.6g} covering {}/{} targets, {} iterations in {:.1f} s", r.tour.cost,
                            r.tour.covered.size(), r.targets.size(), r.iterations, r.seconds));
  reply.status(status_message(*s));
}

std::size_t Daemon::stop_tours(const std::string& scene) {
  std::lock_guard lock(tours_mutex_);
  std::size_t stopped = 0;
  for (auto& [name, flag] : running_tours_) {
    if (!scene.empty() && name != scene) continue;
    if (!flag->exchange(true)) ++stopped;
  }
  return stopped;
}

msg::SceneStatus Daemon::status_message(const RoadmapSession& session) const {
  // Stamped under one lock with the reading, so a later stamp is never an older state.
  std::lock_guard lock(status_mutex_);
  msg::SceneStatus m = to_message(session.status(), config_.server_id, session.published().generation);
  m.status_seq(++status_seq_);
  return m;
}

void Daemon::publish_status(const std::string& scene) {
  if (!dds_) return;
  const auto s = session_or_null(scene);
  if (!s) return;
  std::lock_guard lock(publish_mutex_);
  dds_->publish_status(status_message(*s));
}

void Daemon::publish_unloaded(const std::string& name) {
  msg::SceneStatus status;
  status.scene(name);
  status.server_id(config_.server_id);
  status.state(msg::SCENE_UNLOADED);
  std::lock_guard lock(publish_mutex_);
  {
    std::lock_guard stamp(status_mutex_);
    status.status_seq(++status_seq_);
  }
  dds_->publish_status(status);
}

void Daemon::announce() {
  msg::DaemonInfo info;
  info.server_id(config_.server_id);
  info.host(host_name());
  info.pid(static_cast<std::int32_t>(::getpid()));
  info.available(list_scene_names(config_.scene_dir));
  {
    std::lock_guard lock(sessions_mutex_);
    for (const auto& [name, s] : sessions_) info.loaded().push_back(name);
  }
  dds_->announce(info);
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
