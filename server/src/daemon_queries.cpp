// isparsd's long queries: snapshots in chunks (encoded once per version, kept for the chunks
// that follow) and tours (on the tour workers, stopped by CANCEL on their scene and at shutdown).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "daemon.hpp"
#include "dds_endpoints.hpp"
#include "ispars/gip_solver.hpp"
#include "ispars/inspection_graph.hpp"
#include "ispars/input_error.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

constexpr std::size_t kSnapshotChunk = 1024 * 1024;
constexpr std::size_t kSnapshotsKept = 4;

}  // namespace

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

}  // namespace ispars::server
