// The wire's messages as the client library's types (wire_calls.hpp), and the scene states' names.

#include "ispars/client/wire_calls.hpp"
#include "ispars/wire/convert.hpp"

#include <algorithm>

namespace ispars::client {
namespace {

template <class Names>
std::vector<std::string> strings(const Names& names) {
  std::vector<std::string> out;
  out.reserve(names.size());
  for (const auto& n : names) out.emplace_back(n.to_string());
  return out;
}

template <class Points>
std::vector<Vec3> positions(const Points& points) {
  std::vector<Vec3> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(wire::from_message(p));
  return out;
}

StoredRoadmap from_message(const msg::StoredRoadmap& r) {
  return {r.scene().to_string(),
          r.generation(),
          r.samples(),
          r.target(),
          r.builder_version(),
          r.fingerprint().to_string(),
          r.yielded_to().to_string()};
}

}  // namespace

std::string_view to_string(SceneState state) {
  switch (state) {
    case SceneState::empty:
      return "empty";
    case SceneState::idle:
      return "idle";
    case SceneState::queued:
      return "queued";
    case SceneState::replaying:
      return "replaying";
    case SceneState::building:
      return "building";
    case SceneState::failed:
      return "failed";
    case SceneState::unloaded:
      return "unloaded";
  }
  return "unknown";
}

bool busy(SceneState state) {
  return state == SceneState::queued || state == SceneState::building || state == SceneState::replaying;
}

SceneState from_message(msg::SceneState state) {
  switch (state) {
    case msg::SCENE_EMPTY:
      return SceneState::empty;
    case msg::SCENE_IDLE:
      return SceneState::idle;
    case msg::SCENE_QUEUED:
      return SceneState::queued;
    case msg::SCENE_REPLAYING:
      return SceneState::replaying;
    case msg::SCENE_BUILDING:
      return SceneState::building;
    case msg::SCENE_FAILED:
      return SceneState::failed;
    case msg::SCENE_UNLOADED:
      return SceneState::unloaded;
  }
  // The decoder admits only the enum's values; a newer daemon's state reads as failed.
  return SceneState::failed;
}

SceneStatus from_message(const msg::SceneStatus& s) {
  SceneStatus out;
  out.scene = s.scene().to_string();
  out.server_id = s.server_id().to_string();
  out.status_seq = s.status_seq();
  out.state = from_message(s.state());
  out.method = s.method().to_string();
  out.variant = s.variant().to_string();
  out.seed = s.seed();
  out.generation = s.generation();
  out.accepted_generation = s.accepted_generation();
  out.samples_done = s.samples_done();
  out.samples_target = s.samples_target();
  out.version = s.version();
  out.vertices = s.vertices();
  out.edges = s.edges();
  out.components = s.components();
  out.dense_vertices = s.dense_vertices();
  out.dense_edges = s.dense_edges();
  out.poi_count = s.poi_count();
  out.pois_covered = s.pois_covered();
  out.pois_covered_root = s.pois_covered_root();
  out.dense_delta = s.dense_delta();
  out.sparse_delta = s.sparse_delta();
  out.stretch = s.stretch();
  out.stretch_slack = s.stretch_slack();
  out.stretch_slack_after = s.stretch_slack_after();
  out.p_accept = s.p_accept();
  out.last_error = s.last_error();
  out.scene_fingerprint = s.scene_fingerprint().to_string();
  out.builder_version = s.builder_version();
  out.tasks = s.tasks();
  return out;
}

TaskEntry from_message(const msg::TaskEntry& t) {
  return {t.name().to_string(), t.first_poi(), t.poi_count(), t.pois_covered(), t.pois_covered_root()};
}

SceneEntry from_message(const msg::SceneEntry& e) {
  return {e.scene().to_string(), e.loaded(), e.has_roadmap(), e.server_id().to_string(), e.note()};
}

DaemonInfo from_message(const msg::DaemonInfo& d) {
  DaemonInfo out;
  out.server_id = d.server_id().to_string();
  out.protocol = d.protocol();
  out.host = d.host().to_string();
  out.pid = d.pid();
  out.version = d.version().to_string();
  out.available = strings(d.available());
  out.loaded = strings(d.loaded());
  out.stored = strings(d.stored());
  out.joined_ms = d.joined_ms();
  out.builder_version = d.builder_version();
  for (const auto& r : d.roadmaps()) out.roadmaps.push_back(from_message(r));
  return out;
}

Reply to_reply(const msg::Reply& reply) {
  return {reply.server_id().to_string(), reply.message(), from_message(reply.status())};
}

PathReply to_path_reply(const msg::Reply& reply) {
  PathReply out{to_reply(reply), {}};
  const msg::PathResult& p = reply.body().path();
  out.path = {positions(p.waypoints()), p.length()};
  return out;
}

VerifyReply to_verify_reply(const msg::Reply& reply) {
  const msg::VerifyResult& v = reply.body().verify();
  return {to_reply(reply),
          {v.violations(), v.invalid_vertices(), v.invalid_edges(), v.wrong_costs(), v.sparse_not_dense(),
           v.invariant_violations(), v.invariant_vertices(), v.invariant_promised()}};
}

TourReply to_tour_reply(const msg::Reply& reply) {
  const msg::TourResult& t = reply.body().tour();
  TourReply out{to_reply(reply), {}};
  Tour& tour = out.tour;
  tour.walk = t.walk();
  tour.waypoints = positions(t.waypoints());
  tour.cost = t.cost();
  tour.covered = t.covered();
  tour.target_count = t.target_count();
  tour.lower_bound = t.lower_bound();
  tour.valid = t.valid();
  tour.trace = t.trace();
  tour.bound_trace = t.bound_trace();
  tour.bound_complete = t.bound_complete();
  tour.version = t.version();
  tour.shortcut_stops = t.shortcut_stops();
  tour.shortcut_path = positions(t.shortcut_path());
  tour.shortcut_cost = t.shortcut_cost();
  tour.flown_path = positions(t.flown_path());
  const auto& offsets = t.flown_sees_offsets();
  for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
    const std::uint32_t from = std::min<std::uint32_t>(offsets[i], static_cast<std::uint32_t>(t.flown_sees().size()));
    const std::uint32_t to =
        std::clamp<std::uint32_t>(offsets[i + 1], from, static_cast<std::uint32_t>(t.flown_sees().size()));
    tour.flown_sees.emplace_back(t.flown_sees().begin() + from, t.flown_sees().begin() + to);
  }
  tour.flown_cost = t.flown_cost();
  for (const msg::TourStage& s : t.stages()) tour.stages.push_back({s.name().to_string(), s.cost(), s.seconds()});
  tour.graph_vertices = t.graph_vertices();
  tour.graph_edges = t.graph_edges();
  return out;
}

}  // namespace ispars::client
