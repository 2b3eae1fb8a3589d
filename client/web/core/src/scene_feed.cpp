#include "ispars/web/scene_feed.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <thread>

#include "ispars/params/input_error.hpp"
#include "ispars/scene_files/scene_file.hpp"

namespace ispars::web {

std::string status_message(const client::SceneStatus& s, bool daemon_gone) {
  return nlohmann::json{{"type", "status"},
                        {"daemon_gone", daemon_gone},
                        {"scene", s.scene},
                        {"server_id", s.server_id},
                        {"state", client::to_string(s.state)},
                        {"samples_done", s.samples_done},
                        {"samples_target", s.samples_target},
                        {"vertices", s.vertices},
                        {"edges", s.edges},
                        {"generation", s.generation},
                        {"version", s.version},
                        {"pois_covered", s.pois_covered},
                        {"poi_count", s.poi_count},
                        {"tasks", s.tasks},
                        {"last_error", s.last_error}}
      .dump();
}

void append_roadmap_messages(const Roadmap& roadmap, std::uint64_t generation, const DrawLimits& limits,
                             ViewerCursor& cursor, std::vector<std::string>& out) {
  if (generation != cursor.generation) {
    cursor = ViewerCursor{generation, 0, 0, cursor.last_status};
    out.push_back(nlohmann::json{{"type", "reset"}, {"generation", generation}}.dump());
  }
  const std::size_t vertex_end = std::min(roadmap.vertex_count(), limits.vertices);
  const std::size_t edge_end = std::min(roadmap.edge_count(), limits.edges);
  const bool cut = roadmap.vertex_count() > limits.vertices || roadmap.edge_count() > limits.edges;
  const std::string note = cut ? fmt::format(
                                     "drawing the first {} of {} vertices and {} of {} edges (the viewer's "
                                     "limit)",
                                     vertex_end, roadmap.vertex_count(), edge_end, roadmap.edge_count())
                               : std::string();
  while (cursor.vertices < vertex_end || cursor.edges < edge_end) {
    const std::size_t v1 = std::min(vertex_end, cursor.vertices + limits.per_message);
    nlohmann::json positions = nlohmann::json::array();
    for (std::size_t v = cursor.vertices; v < v1; ++v) {
      const Vec3& p = roadmap.position(static_cast<VertexId>(v));
      positions.push_back(p.x());
      positions.push_back(p.y());
      positions.push_back(p.z());
    }
    // An edge to a vertex of a later batch waits for it; once every vertex within the limit is
    // sent, an edge with an end past the limit is left out.
    const bool all_vertices = v1 == vertex_end;
    std::size_t e1 = cursor.edges;
    nlohmann::json edges = nlohmann::json::array();
    for (const std::size_t cap = std::min(edge_end, cursor.edges + limits.per_message); e1 < cap; ++e1) {
      const RoadmapEdge edge = roadmap.edge(e1);
      if (edge.u >= v1 || edge.v >= v1) {
        if (!all_vertices) break;
        continue;
      }
      edges.push_back(edge.u);
      edges.push_back(edge.v);
    }
    out.push_back(nlohmann::json{
        {"type", "batch"},
        {"generation", generation},
        {"first_vertex", cursor.vertices},
        {"positions", std::move(positions)},
        {"edges", std::move(edges)},
        {"vertices_total", roadmap.vertex_count()},
        {"edges_total", roadmap.edge_count()},
        {"vertices_sent", v1},
        {"edges_sent", e1},
        {"note",
         note}}.dump());
    cursor.vertices = v1;
    cursor.edges = e1;
  }
}

SceneFeed::SceneFeed(client::Client& client, std::string scene, DrawLimits limits)
    : client_(client), scene_(std::move(scene)), limits_(limits) {
  (void)client_.stats(scene_);  // throws, naming the problem, when no daemon holds the scene
  replica_ = std::make_unique<client::RoadmapReplica>(client_, scene_,
                                                      [this](const client::ReplicaEvent& e) { on_change(e); });
  replica_ready_ = replica_.get();
}

SceneFeed::~SceneFeed() {
  replica_ready_ = nullptr;
  replica_.reset();  // joins the replica's thread
}

void SceneFeed::on_change(const client::ReplicaEvent& event) {
  ++changes_;
  if (event.resynced) {  // rare (a sync from a snapshot), and what an operator asks about first
    spdlog::info("ispars-web: scene {}: synced from a snapshot at version {} of roadmap {} ({} vertices)", scene_,
                 event.version, event.generation, event.vertices);
  }
}

std::shared_ptr<const Roadmap> SceneFeed::current(std::uint64_t& generation) {
  std::lock_guard lock(copy_mutex_);
  client::RoadmapReplica* replica = replica_ready_;
  const std::uint64_t changes = changes_;
  if (replica != nullptr && changes != copied_changes_) {
    roadmap_ = std::make_shared<const Roadmap>(replica->roadmap());
    generation_ = replica->generation();
    copied_changes_ = changes;
  }
  generation = generation_;
  return roadmap_;
}

std::optional<std::string> SceneFeed::scene_update_for(record::SceneUpdateCursor& cursor) {
  log_sync_error();
  std::uint64_t generation = 0;
  const std::shared_ptr<const Roadmap> roadmap = current(generation);
  if (!roadmap) return std::nullopt;
  std::optional<nlohmann::json> update = cursor.next(*roadmap, generation, 0, record::now_ns());
  if (!update) return std::nullopt;
  return update->dump();
}

std::vector<std::string> SceneFeed::updates_for(ViewerCursor& cursor) {
  std::vector<std::string> out;
  // A holder that left the domain (its participant's lease ran out) takes its statuses with it:
  // the last one seen is shown, saying so, until a daemon holds the scene again.
  std::optional<client::SceneStatus> status = client_.latest_status(scene_);
  bool gone = false;
  {
    std::lock_guard lock(mutex_);
    if (status) {
      last_status_ = status;
    } else if (last_status_) {
      status = last_status_;
      gone = true;
    }
  }
  if (status && !gone) gone = client_.daemon_identity(status->server_id).empty();
  if (status) {
    std::string message = status_message(*status, gone);
    if (message != cursor.last_status) {
      cursor.last_status = message;
      out.push_back(std::move(message));
    }
  }
  log_sync_error();
  std::uint64_t generation = 0;
  const std::shared_ptr<const Roadmap> roadmap = current(generation);
  if (roadmap) append_roadmap_messages(*roadmap, generation, limits_, cursor, out);
  return out;
}

void SceneFeed::log_sync_error() {
  if (changes_.load() > 0) return;  // synced once (a change follows the first snapshot): nothing to say
  client::RoadmapReplica* replica = replica_ready_;
  if (replica == nullptr || replica->snapshots_taken() > 0) return;
  std::string why = replica->last_error();
  std::lock_guard lock(mutex_);
  if (why.empty() || why == logged_sync_error_) return;
  spdlog::warn("ispars-web: scene {}: no snapshot yet (trying again): {}", scene_, why);
  logged_sync_error_ = std::move(why);
}

std::string SceneFeed::tasks_message() {
  const std::vector<client::TaskEntry> tasks = client_.tasks(scene_);
  client::RoadmapReplica* replica = replica_ready_;
  const std::vector<Vec3> pois = replica != nullptr ? replica->pois() : std::vector<Vec3>{};
  nlohmann::json list = nlohmann::json::array();
  std::size_t shown = 0;
  for (const client::TaskEntry& t : tasks) {
    nlohmann::json entry{{"name", t.name},
                         {"first_poi", t.first_poi},
                         {"poi_count", t.poi_count},
                         {"pois_covered", t.pois_covered},
                         {"pois_covered_root", t.pois_covered_root}};
    // The replica may not hold a task added a moment ago: its positions come with the next ask.
    const bool held = std::size_t{t.first_poi} + t.poi_count <= pois.size();
    if (held && shown + t.poi_count <= kMaxTaskPoisShown) {
      nlohmann::json xyz = nlohmann::json::array();
      for (std::size_t i = t.first_poi; i < std::size_t{t.first_poi} + t.poi_count; ++i) {
        xyz.push_back(pois[i].x());
        xyz.push_back(pois[i].y());
        xyz.push_back(pois[i].z());
      }
      entry["positions"] = std::move(xyz);
      shown += t.poi_count;
    } else {
      entry["not_drawn"] = held ? fmt::format("past the viewer's {} task POIs", kMaxTaskPoisShown)
                                : std::string("not yet: the gateway's replica does not hold its POIs yet");
    }
    list.push_back(std::move(entry));
  }
  return nlohmann::json{{"type", "tasks"}, {"tasks", std::move(list)}}.dump();
}

std::shared_ptr<const std::string> SceneFeed::mesh(const std::filesystem::path& scene_dir, std::string& why) {
  // The daemon's POIs come with the replica's first snapshot: wait for it (bounded), so that a
  // mesh asked for at once is not judged against no POIs.
  client::RoadmapReplica* replica = replica_ready_;
  const auto deadline = std::chrono::steady_clock::now() + client_.options().timeout;
  while (replica != nullptr && replica->snapshots_taken() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (replica == nullptr || replica->snapshots_taken() == 0) {
    why = "no mesh yet: the scene's roadmap has not reached the gateway";  // not kept: asked again next time
    return nullptr;
  }
  // One request loads the mesh, with no lock held; others asking meanwhile wait for it (browsers
  // of the scene keep being served: their updates take no lock of the mesh).
  std::unique_lock lock(mesh_mutex_);
  mesh_loaded_.wait(lock, [this] { return !mesh_loading_; });
  if (!mesh_) {
    mesh_loading_ = true;
    lock.unlock();
    std::shared_ptr<const std::string> loaded;
    std::string error;
    try {
      loaded = load_mesh(scene_dir, *replica);
    } catch (const std::exception& e) {
      error = e.what();
    }
    lock.lock();
    mesh_ = std::move(loaded);
    mesh_error_ = std::move(error);
    mesh_loading_ = false;
    mesh_loaded_.notify_all();
  }
  why = mesh_error_;
  return *mesh_;
}

std::shared_ptr<const std::string> SceneFeed::load_mesh(const std::filesystem::path& scene_dir,
                                                        const client::RoadmapReplica& replica) const {
  const std::filesystem::path file = scene_dir / (scene_ + ".yaml");
  if (scene_dir.empty() || !std::filesystem::exists(file)) {
    throw std::runtime_error(fmt::format("no mesh: {} is not in the gateway's scene directory", scene_ + ".yaml"));
  }
  const scene_files::SceneFile scene =
      scene_files::read_scene_file(file);  // no collision or visibility checks: only shown here
  const std::vector<Vec3> pois = replica.pois();
  // The daemon's POIs begin with the scene file's; its inspection tasks' follow.
  bool same = pois.size() >= scene.pois.size();
  for (std::size_t i = 0; same && i < scene.pois.size(); ++i) same = (pois[i] - scene.pois[i]).norm() < 1e-6;
  if (!same) {
    throw std::runtime_error(
        fmt::format("no mesh: {} in the gateway's scene directory is not the daemon's scene "
                    "(its POIs differ)",
                    file.filename().string()));
  }
  const scene_files::TriangleMesh& m = scene.mesh;
  auto bytes = std::make_shared<std::string>();
  const auto put = [&](const void* data, std::size_t size) { bytes->append(static_cast<const char*>(data), size); };
  const auto nv = static_cast<std::uint32_t>(m.vertices.size());
  const auto nt = static_cast<std::uint32_t>(m.triangles.size());
  put(&nv, 4);
  put(&nt, 4);
  for (const auto& v : m.vertices) put(v.data(), 12);
  for (const auto& t : m.triangles) put(t.data(), 12);
  return bytes;
}

}  // namespace ispars::web
