#include "ispars/wire/convert.hpp"

#include <stdexcept>

namespace ispars::wire {

msg::Point to_message(const Vec3& p) {
  msg::Point m;
  m.x(p.x());
  m.y(p.y());
  m.z(p.z());
  return m;
}

Vec3 from_message(const msg::Point& p) { return {p.x(), p.y(), p.z()}; }

msg::UpdateBatch to_message(const RoadmapBatch& batch, const std::string& scene, const std::string& server_id,
                            std::uint64_t generation, std::uint64_t samples_done) {
  msg::UpdateBatch m;
  m.scene(scene);
  m.server_id(server_id);
  m.generation(generation);
  m.from_version(batch.from_version);
  m.to_version(batch.to_version);
  m.samples_done(samples_done);
  m.order().reserve(batch.changes.size());
  for (const RoadmapChange& c : batch.changes) m.order().push_back(c.kind == RoadmapChange::Kind::vertex ? 0 : 1);
  std::size_t vertex = 0;
  m.vertices().resize(batch.positions.size());
  for (const RoadmapChange& c : batch.changes) {
    if (c.kind != RoadmapChange::Kind::vertex) continue;
    msg::Vertex& v = m.vertices()[vertex];
    v.id(c.index);
    v.position(to_message(batch.positions[vertex]));
    v.pois().assign(batch.visible[vertex].begin(), batch.visible[vertex].end());
    ++vertex;
  }
  for (const RoadmapChange& c : batch.changes) {
    if (c.kind == RoadmapChange::Kind::edge) {
      m.first_edge(c.index);
      break;
    }
  }
  m.edges().resize(batch.edges.size());
  for (std::size_t i = 0; i < batch.edges.size(); ++i) {
    m.edges()[i].u(batch.edges[i].u);
    m.edges()[i].v(batch.edges[i].v);
    m.edges()[i].cost(batch.edges[i].cost);
  }
  return m;
}

RoadmapBatch from_message(const msg::UpdateBatch& m) {
  if (m.to_version() < m.from_version() || m.to_version() - m.from_version() != m.order().size()) {
    throw std::runtime_error("update batch version range does not match its change count");
  }
  RoadmapBatch batch;
  batch.from_version = m.from_version();
  batch.to_version = m.to_version();
  std::size_t vertex = 0;
  std::size_t edge = 0;
  // Edge indices are consecutive from first_edge; the replica checks them against its own count.
  std::uint32_t next_edge_index = m.first_edge();
  for (const std::uint8_t kind : m.order()) {
    if (kind == 0) {
      if (vertex >= m.vertices().size()) throw std::runtime_error("update batch has too few vertices");
      const msg::Vertex& v = m.vertices()[vertex++];
      batch.changes.push_back({RoadmapChange::Kind::vertex, v.id()});
      batch.positions.push_back(from_message(v.position()));
      batch.visible.emplace_back(v.pois().begin(), v.pois().end());
    } else if (kind == 1) {
      if (edge >= m.edges().size()) throw std::runtime_error("update batch has too few edges");
      const msg::Edge& e = m.edges()[edge++];
      batch.changes.push_back({RoadmapChange::Kind::edge, next_edge_index++});
      batch.edges.push_back({e.u(), e.v(), e.cost()});
    } else {
      throw std::runtime_error("update batch has an unknown change kind");
    }
  }
  if (vertex != m.vertices().size() || edge != m.edges().size()) {
    throw std::runtime_error("update batch has more vertices or edges than its order lists");
  }
  return batch;
}

std::string to_string(msg::SceneState state) {
  switch (state) {
    case msg::SCENE_EMPTY:
      return "empty";
    case msg::SCENE_IDLE:
      return "idle";
    case msg::SCENE_QUEUED:
      return "queued";
    case msg::SCENE_REPLAYING:
      return "replaying";
    case msg::SCENE_BUILDING:
      return "building";
    case msg::SCENE_FAILED:
      return "failed";
    case msg::SCENE_UNLOADED:
      return "unloaded";
  }
  return "unknown";
}

std::string to_string(msg::Operation operation) {
  switch (operation) {
    case msg::LIST_SCENES:
      return "list";
    case msg::LOAD_SCENE:
      return "load";
    case msg::UNLOAD_SCENE:
      return "unload";
    case msg::BUILD:
      return "build";
    case msg::EXTEND:
      return "extend";
    case msg::CANCEL:
      return "cancel";
    case msg::STATS:
      return "stats";
    case msg::PATH:
      return "path";
    case msg::SNAPSHOT:
      return "snapshot";
    case msg::DROP:
      return "drop";
    case msg::VERIFY:
      return "verify";
    case msg::TOUR:
      return "tour";
    case msg::TASK_ADD:
      return "task add";
    case msg::TASK_LIST:
      return "task list";
    case msg::TASK_REMOVE:
      return "task remove";
  }
  return "unknown";
}

msg::ReplyBody empty_reply_body(msg::Operation operation) {
  msg::ReplyBody body;
  switch (operation) {
    case msg::LIST_SCENES:
      body.list_scenes(msg::SceneList{});
      break;
    case msg::LOAD_SCENE:
      body.load_scene(msg::NoArgs{});
      break;
    case msg::UNLOAD_SCENE:
      body.unload_scene(msg::NoArgs{});
      break;
    case msg::BUILD:
      body.build(msg::NoArgs{});
      break;
    case msg::EXTEND:
      body.extend(msg::NoArgs{});
      break;
    case msg::CANCEL:
      body.cancel(msg::NoArgs{});
      break;
    case msg::STATS:
      body.stats(msg::NoArgs{});
      break;
    case msg::PATH:
      body.path(msg::PathResult{});
      break;
    case msg::SNAPSHOT:
      body.snapshot(msg::SnapshotChunk{});
      break;
    case msg::DROP:
      body.drop(msg::NoArgs{});
      break;
    case msg::VERIFY:
      body.verify(msg::VerifyResult{});
      break;
    case msg::TOUR:
      body.tour(msg::TourResult{});
      break;
    case msg::TASK_ADD:
      body.task_add(msg::NoArgs{});
      break;
    case msg::TASK_LIST:
      body.task_list(msg::TaskList{});
      break;
    case msg::TASK_REMOVE:
      body.task_remove(msg::NoArgs{});
      break;
  }
  return body;
}

msg::QueryArgs query_args(msg::Operation operation) {
  msg::QueryArgs args;
  switch (operation) {
    case msg::LIST_SCENES:
      args.list_scenes(msg::NoArgs{});
      break;
    case msg::STATS:
      args.stats(msg::NoArgs{});
      break;
    case msg::PATH:
      args.path(msg::PathArgs{});
      break;
    case msg::SNAPSHOT:
      args.snapshot(msg::SnapshotArgs{});
      break;
    case msg::VERIFY:
      args.verify(msg::NoArgs{});
      break;
    case msg::TOUR:
      args.tour(msg::TourArgs{});
      break;
    case msg::TASK_LIST:
      args.task_list(msg::NoArgs{});
      break;
    default:
      throw std::invalid_argument(to_string(operation) + " is not a query");
  }
  return args;
}

msg::ChangeArgs change_args(msg::Operation operation) {
  msg::ChangeArgs args;
  switch (operation) {
    case msg::LOAD_SCENE:
      args.load_scene(msg::NoArgs{});
      break;
    case msg::UNLOAD_SCENE:
      args.unload_scene(msg::NoArgs{});
      break;
    case msg::BUILD:
      args.build(msg::BuildArgs{});
      break;
    case msg::EXTEND:
      args.extend(msg::ExtendArgs{});
      break;
    case msg::CANCEL:
      args.cancel(msg::NoArgs{});
      break;
    case msg::DROP:
      args.drop(msg::NoArgs{});
      break;
    case msg::TASK_ADD:
      args.task_add(msg::TaskAddArgs{});
      break;
    case msg::TASK_REMOVE:
      args.task_remove(msg::TaskRemoveArgs{});
      break;
    default:
      throw std::invalid_argument(to_string(operation) + " is not a change");
  }
  return args;
}

}  // namespace ispars::wire
