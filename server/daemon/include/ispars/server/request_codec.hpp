#pragma once
// Between the wire and the service, with no DDS: a request's arguments decoded into the
// service's typed form, and the service's results encoded into reply messages (a build's
// arguments: wire/build_args.hpp). Decoding checks only what the typed form cannot hold; the
// values are the service's to check.

#include <span>
#include <string>

#include "ispars.h"
#include "ispars/service/roadmap_service.hpp"

namespace ispars::server {

/// "build", or "operation 42" for a code this daemon does not know.
[[nodiscard]] std::string operation_name(msg::Operation operation);

/// TASK_ADD's arguments as a task on `scene`: its POIs as given, or `sample` drawn on the
/// surface (sample_task_pois). Throws InputError ("request", task.pois / task.sample) for more
/// than MAX_TASK_POIS POIs, both POIs and a sample count, or neither. The POIs are the
/// service's to check (check_task).
[[nodiscard]] service::InspectionTask task_from(const msg::TaskAddArgs& args, const planning::Scene& scene);

/// TASK_LIST's reply: each task's POI ids and coverage.
[[nodiscard]] msg::TaskList to_message(std::span<const service::TaskCoverage> tasks);

/// A verify's reply: its report and the violations the method promises to avoid.
[[nodiscard]] msg::VerifyResult to_message(const service::VerifyOutcome& v);
/// A verify's one-line summary, for the reply's message: each count, what Invariant 1 was checked
/// on (the fresh samples drawn for the check, else the `dense_vertices` dense vertices), and
/// whether the method promises it.
[[nodiscard]] std::string verify_summary(const service::VerifyOutcome& v, std::size_t dense_vertices);

/// A path's reply: its waypoints and length.
[[nodiscard]] msg::PathResult to_message(const planning::RoadmapPath& path);

/// A snapshot chunk: the slice's bytes and counters; the first chunk (index 0) also carries the
/// scene's root and POIs, from `first` (which the other chunks do not need: null for them).
[[nodiscard]] msg::SnapshotChunk to_message(const service::SnapshotSlice& slice, const planning::Scene* first);

/// A tour's reply: the walk and its waypoints, the shortcut tour, costs, coverage, the proven
/// bound (0: none), the traces as (seconds, value) pairs flattened, and valid when both the walk
/// and the shortcut tour passed their independent checks.
[[nodiscard]] msg::TourResult to_message(const service::TourOutcome& o);

}  // namespace ispars::server
