#include "ispars/server/request_codec.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "ispars/params/input_error.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {

std::string operation_name(msg::Operation operation) {
  const std::string name = wire::to_string(operation);
  return name != "unknown" ? name : fmt::format("operation {}", static_cast<int>(operation));
}

msg::VerifyResult to_message(const service::VerifyOutcome& v) {
  msg::VerifyResult m;
  m.violations(v.violations());
  m.invalid_vertices(v.report.invalid_vertices);
  m.invalid_edges(v.report.invalid_edges);
  m.wrong_costs(v.report.wrong_costs);
  m.sparse_not_dense(v.report.sparse_not_dense);
  m.invariant_violations(v.report.invariant_violations);
  m.invariant_vertices(v.report.invariant_vertices);
  m.invariant_promised(v.invariant_promised);
  return m;
}

msg::TourResult to_message(const service::TourOutcome& o) {
  const planning::GipResult& r = o.result;
  msg::TourResult m;
  m.walk(std::vector<std::uint32_t>(r.tour.walk.begin(), r.tour.walk.end()));
  for (const Vec3& p : o.waypoints) m.waypoints().push_back(wire::to_message(p));
  m.shortcut_stops(std::vector<std::uint32_t>(o.shortcut.stops.begin(), o.shortcut.stops.end()));
  for (const Vec3& p : o.shortcut.path) m.shortcut_path().push_back(wire::to_message(p));
  m.shortcut_cost(o.shortcut.cost);
  m.cost(r.tour.cost);
  m.covered(static_cast<std::uint32_t>(r.tour.covered.size()));
  m.target_count(static_cast<std::uint32_t>(r.targets.size()));
  m.lower_bound(r.lower_bound.value_or(0.0));
  // The walk, its shortcut and the flown tour: each passed its independent check.
  m.valid(r.validation.valid() && o.shortcut_validation.valid() && o.flown_valid);
  for (const Vec3& p : o.flown_path) m.flown_path().push_back(wire::to_message(p));
  m.flown_sees_offsets().push_back(0);
  for (const std::vector<PoiId>& seen : o.flown_sees) {
    m.flown_sees().insert(m.flown_sees().end(), seen.begin(), seen.end());
    m.flown_sees_offsets().push_back(static_cast<std::uint32_t>(m.flown_sees().size()));
  }
  m.flown_cost(o.flown_cost);
  for (const planning::FlownStage& s : o.stages) {
    msg::TourStage stage;
    stage.name(s.name);
    stage.cost(s.cost);
    stage.seconds(s.seconds);
    m.stages().push_back(std::move(stage));
  }
  m.graph_vertices(o.graph_vertices);
  m.graph_edges(o.graph_edges);
  for (const auto& [t, c] : r.trace) {
    m.trace().push_back(t);
    m.trace().push_back(c);
  }
  for (const auto& [t, b] : r.bound_trace) {
    m.bound_trace().push_back(t);
    m.bound_trace().push_back(b);
  }
  m.bound_complete(r.bound_complete);
  m.version(o.version);
  return m;
}

std::string verify_summary(const service::VerifyOutcome& v, std::size_t dense_vertices) {
  const planning::VerificationReport& r = v.report;
  const std::string checked_on =
      r.invariant_drawn > 0
          ? fmt::format("{} of the {} samples the build drew (drawn again)", r.invariant_vertices, r.invariant_drawn)
      : r.invariant_samples > 0
          ? fmt::format(
                "{} of {} fresh samples, drawn for this check: an estimate, not counted; every sample "
                "the build drew keeps it",
                r.invariant_vertices, r.invariant_samples)
          : fmt::format("{} of {} dense vertices", r.invariant_vertices, dense_vertices);
  return fmt::format(
      "invalid vertices {}, invalid edges {}, wrong costs {}, sparse not dense {}, "
      "Invariant 1 violations {} ({} have one){}",
      r.invalid_vertices, r.invalid_edges, r.wrong_costs, r.sparse_not_dense, r.invariant_violations, checked_on,
      v.invariant_promised ? "" : "; Invariant 1 is not promised by this method");
}

msg::PathResult to_message(const planning::RoadmapPath& path) {
  msg::PathResult result;
  for (const Vec3& p : path.waypoints) result.waypoints().push_back(wire::to_message(p));
  result.length(path.length);
  return result;
}

service::InspectionTask task_from(const msg::TaskAddArgs& args, const planning::Scene& scene) {
  service::InspectionTask task;
  task.name = args.name().to_string();
  if (args.pois().size() > msg::MAX_TASK_POIS) {
    throw params::InputError("request", "task.pois",
                             fmt::format("{} POIs; a task has at most {}", args.pois().size(), msg::MAX_TASK_POIS));
  }
  if (!args.pois().empty() && args.sample() != 0) {
    throw params::InputError("request", "task.sample", "give the task's POIs or a count to sample, not both");
  }
  if (args.pois().empty() && args.sample() == 0) {
    throw params::InputError("request", "task.pois", "a task has at least one POI: give them, or a count to sample");
  }
  if (args.sample() != 0) {
    task.pois = service::sample_task_pois(scene, args.sample(), args.sample_seed());
  } else {
    task.pois.reserve(args.pois().size());
    for (const msg::Point& p : args.pois()) task.pois.push_back(wire::from_message(p));
  }
  return task;
}

msg::TaskList to_message(std::span<const service::TaskCoverage> tasks) {
  msg::TaskList list;
  for (const service::TaskCoverage& t : tasks) {
    msg::TaskEntry e;
    e.name(t.name);
    e.first_poi(static_cast<std::uint32_t>(t.first_poi));
    e.poi_count(static_cast<std::uint32_t>(t.poi_count));
    e.pois_covered(static_cast<std::uint32_t>(t.covered));
    e.pois_covered_root(static_cast<std::uint32_t>(t.covered_root));
    list.tasks().push_back(std::move(e));
  }
  return list;
}

msg::SnapshotChunk to_message(const service::SnapshotSlice& slice, const planning::Scene* first) {
  msg::SnapshotChunk chunk;
  chunk.generation(slice.generation);
  chunk.version(slice.version);
  chunk.chunk_index(slice.chunk_index);
  chunk.chunk_count(slice.chunk_count);
  chunk.bytes().assign(slice.encoded->begin() + static_cast<std::ptrdiff_t>(slice.begin),
                       slice.encoded->begin() + static_cast<std::ptrdiff_t>(slice.end));
  if (slice.chunk_index == 0 && first != nullptr) {
    chunk.root(wire::to_message(first->config().root));
    const auto& pois = first->pois();
    const std::size_t count = std::min(pois.size(), slice.poi_count);
    for (std::size_t i = 0; i < count; ++i) chunk.pois().push_back(wire::to_message(pois[i]));
  }
  return chunk;
}

}  // namespace ispars::server
