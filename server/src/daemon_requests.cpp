// isparsd's operations: each request's arguments decoded into the service's typed form, the
// service called, and its result encoded into the reply. Nothing here decides anything the
// service should: values are checked there.

#include <fmt/format.h>

#include "daemon.hpp"
#include "dds_endpoints.hpp"
#include "ispars/input_error.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {
namespace {

std::string operation_name(msg::Operation operation) {
  const std::string name = wire::to_string(operation);
  return name != "unknown" ? name : fmt::format("operation {}", static_cast<int>(operation));
}

BuildRequest build_request_from(const msg::BuildArgs& args) {
  const std::string method_name = args.method().to_string();
  const auto method = parse_build_method(method_name);
  if (!method) {
    throw InputError("request", "method", fmt::format("'{}' is not one of {}", method_name, build_method_names()));
  }
  const std::string variant_name = args.variant().to_string();
  const auto variant = variant_name.empty() ? SparsVariant::stretch : parse_spars_variant(variant_name);
  if (!variant) {
    throw InputError("request", "variant", fmt::format("'{}' is not one of {}", variant_name, spars_variant_names()));
  }
  if (!variant_name.empty() && !has_variants(*method)) {
    throw InputError("request", "variant",
                     fmt::format("'{}' given, but {} has no rule-set variants (spars and ispars have)", variant_name,
                                 method_name));
  }
  if (args.overrides().size() > msg::MAX_OVERRIDES) {
    throw InputError("request", "overrides",
                     fmt::format("{} given; at most {} allowed", args.overrides().size(), msg::MAX_OVERRIDES));
  }
  BuildRequest build;
  build.method = *method;
  build.variant = *variant;
  build.samples = args.samples();
  build.seed = args.seed();
  build.replace = args.replace();
  for (const auto& o : args.overrides()) {
    if (!build.overrides.emplace(o.name().to_string(), o.value()).second) {
      throw InputError("request", "overrides." + o.name().to_string(), "given twice");
    }
  }
  return build;
}

msg::VerifyResult to_message(const VerifyOutcome& v) {
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

msg::TourResult to_message(const TourOutcome& o) {
  const GipResult& r = o.result;
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
  m.valid(r.validation.valid() && o.shortcut_validation.valid());  // the walk and the shortcut path both
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

}  // namespace

bool Daemon::answer(const msg::QueryRequest& request, msg::Reply& reply) {
  const std::string scene = request.scene().to_string();
  const msg::QueryArgs& args = request.args();
  switch (args._d()) {
    case msg::LIST_SCENES: {
      msg::SceneList list;
      for (const SceneListing& l : service_->list_scenes()) {
        msg::SceneEntry e;
        e.scene(l.name);
        e.loaded(l.loaded);
        e.has_roadmap(l.has_roadmap);
        e.server_id(config_.server_id);
        e.note(fleet_note(l.name));
        list.scenes().push_back(e);
      }
      reply.body().list_scenes(std::move(list));
      return true;
    }
    case msg::STATS:
      reply.status(status_message(*service_->session(scene)));
      return true;
    case msg::PATH: {
      const RoadmapPath path =
          service_->path(scene, wire::from_message(args.path().from()), wire::from_message(args.path().to()));
      msg::PathResult result;
      for (const Vec3& p : path.waypoints) result.waypoints().push_back(wire::to_message(p));
      result.length(path.length);
      reply.body().path(std::move(result));
      reply.status(status_message(*service_->session(scene)));
      return true;
    }
    case msg::SNAPSHOT: {
      const msg::SnapshotArgs& a = args.snapshot();
      const SnapshotSlice slice = service_->snapshot(scene, a.version(), a.generation(), a.chunk_index());
      msg::SnapshotChunk chunk;
      chunk.generation(slice.generation);
      chunk.version(slice.version);
      chunk.chunk_index(slice.chunk_index);
      chunk.chunk_count(slice.chunk_count);
      chunk.bytes().assign(slice.encoded->begin() + static_cast<std::ptrdiff_t>(slice.begin),
                           slice.encoded->begin() + static_cast<std::ptrdiff_t>(slice.end));
      if (slice.chunk_index == 0) {
        const auto s = service_->session(scene);
        reply.status(status_message(*s));
        chunk.root(wire::to_message(s->scene().config().root));
        for (const Vec3& p : s->scene().pois()) chunk.pois().push_back(wire::to_message(p));
      }
      reply.body().snapshot(std::move(chunk));
      return true;
    }
    case msg::VERIFY: {
      const VerifyOutcome v = service_->verify(scene);
      const VerificationReport& r = v.report;
      const std::size_t dense_vertices = service_->stats(scene).dense_vertices;
      const std::string checked_on =
          r.invariant_samples > 0
              ? fmt::format("{} of {} fresh samples, drawn for this check: an estimate, not counted; every sample "
                            "the build drew keeps it",
                            r.invariant_vertices, r.invariant_samples)
              : fmt::format("{} of {} dense vertices", r.invariant_vertices, dense_vertices);
      reply.message(fmt::format("invalid vertices {}, invalid edges {}, wrong costs {}, sparse not dense {}, "
                                "Invariant 1 violations {} ({} have one){}",
                                r.invalid_vertices, r.invalid_edges, r.wrong_costs, r.sparse_not_dense,
                                r.invariant_violations, checked_on,
                                v.invariant_promised ? "" : "; Invariant 1 is not promised by this method"));
      reply.body().verify(to_message(v));
      reply.status(status_message(*service_->session(scene)));
      return true;
    }
    case msg::TOUR:
      start_tour(request, reply);
      return false;
    default:
      throw InputError("request", "operation",
                       fmt::format("{} is not a query (list, stats, path, snapshot, verify, tour); changes go on the "
                                   "change topic",
                                   operation_name(args._d())));
  }
}

bool Daemon::answer(const msg::ChangeRequest& request, msg::Reply& reply) {
  const std::string scene = request.scene().to_string();
  const msg::ChangeArgs& args = request.args();
  switch (args._d()) {
    case msg::LOAD_SCENE: {
      const auto [s, loaded_now] = service_->load(scene);
      reply.message(!loaded_now                       ? fmt::format("scene '{}' was already loaded", scene)
                    : s->recovery_note().empty() ? fmt::format("loaded scene '{}'", scene)
                                                 : s->recovery_note());
      reply.status(status_message(*s));
      return true;
    }
    case msg::UNLOAD_SCENE:
      service_->unload(scene);
      reply.message(fmt::format("unloaded scene '{}' (its stored roadmap stays on disk)", scene));
      return true;
    case msg::BUILD: {
      const msg::BuildArgs& a = args.build();
      service_->build(scene, build_request_from(a));
      reply.message(fmt::format("building {} on '{}': {} samples, seed {}", a.method().to_string(), scene, a.samples(),
                                a.seed()));
      break;
    }
    case msg::EXTEND:
      service_->extend(scene, args.extend().samples());
      reply.message(fmt::format("extending '{}' by {} samples", scene, args.extend().samples()));
      break;
    case msg::CANCEL: {
      const CancelOutcome c = service_->cancel(scene);
      reply.message(fmt::format("{}; {} tour{} stopped (each replies with its best tour so far)",
                                c.build_cancelled ? "cancelling the build after the current chunk" : "no build running",
                                c.tours_stopped, c.tours_stopped == 1 ? "" : "s"));
      break;
    }
    case msg::DROP:
      service_->drop(scene);
      with_dds([&](DdsEndpoints& d) { d.retire_updates(scene); });  // replicas drop their copy; the kept batches are released
      reply.message(fmt::format("dropped the roadmap of '{}'", scene));
      break;
    default:
      throw InputError("request", "operation",
                       fmt::format("{} is not a change (load, unload, build, extend, cancel, drop); queries go on "
                                   "the query topic",
                                   operation_name(args._d())));
  }
  reply.status(status_message(*service_->session(scene)));
  return true;
}

void Daemon::start_tour(const msg::QueryRequest& request, const msg::Reply& header) {
  const msg::TourArgs& a = request.args().tour();
  TourRequest tour;
  if (a.targets().size() > msg::MAX_TOUR_TARGETS) {
    throw InputError("request", "targets", fmt::format("{} given; at most {}", a.targets().size(), msg::MAX_TOUR_TARGETS));
  }
  tour.targets.assign(a.targets().begin(), a.targets().end());
  tour.budget_seconds = a.budget();
  tour.seed = a.seed();
  const std::string scene = request.scene().to_string();
  const auto taken = std::chrono::steady_clock::now();
  TourCallbacks callbacks;
  callbacks.progress = [this, header, scene](double seconds, double cost, double bound) {
    msg::TourProgress progress;
    progress.client_id(header.client_id());
    progress.request_seq(header.request_seq());
    progress.scene(scene);
    progress.seconds(seconds);
    progress.cost(cost);
    progress.lower_bound(bound);
    with_dds([&](DdsEndpoints& d) { d.publish_tour_progress(progress); });
  };
  callbacks.done = [this, header, scene, taken](TourOutcome outcome) {
    msg::Reply reply = header;
    const GipResult& r = outcome.result;
    reply.message(fmt::format("tour of cost {:.6g} covering {}/{} targets, {} iterations in {:.1f} s", r.tour.cost,
                              r.tour.covered.size(), r.targets.size(), r.iterations, r.seconds));
    reply.body().tour(to_message(outcome));
    try {
      reply.status(status_message(*service_->session(scene)));
    } catch (const std::exception&) {
      // unloaded meanwhile: the tour still stands, on the version it names
    }
    finish(reply, taken);
  };
  callbacks.failed = [this, header, taken](const std::string& error) {
    msg::Reply reply = header;
    reply.ok(false);
    reply.error(error);
    finish(reply, taken);
  };
  service_->start_tour(scene, std::move(tour), std::move(callbacks));
}

}  // namespace ispars::server
