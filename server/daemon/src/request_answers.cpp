// isparsd's operations: each request's arguments decoded into the service's typed form
// (request_codec.hpp), the service called, and its result encoded into the reply. Nothing here
// decides anything the service should: values are checked there.

#include <fmt/format.h>

#include "ispars/params/input_error.hpp"
#include "ispars/server/request_codec.hpp"
#include "ispars/server/request_router.hpp"
#include "ispars/wire/build_args.hpp"
#include "ispars/wire/convert.hpp"

namespace ispars::server {

bool RequestRouter::answer(const msg::QueryRequest& request, msg::Reply& reply) {
  const std::string scene = request.scene().to_string();
  if (!scene.empty()) (void)parts_.gate.wait(scene);  // not the empty roadmap of a takeover half done
  const msg::QueryArgs& args = request.args();
  switch (args._d()) {
    case msg::LIST_SCENES: {
      msg::SceneList list;
      for (const service::SceneListing& l : parts_.service.list_scenes()) {
        msg::SceneEntry e;
        e.scene(l.name);
        e.loaded(l.loaded);
        e.has_roadmap(l.has_roadmap);
        e.server_id(parts_.server_id);
        e.note(parts_.note(l.name));
        list.scenes().push_back(e);
      }
      reply.body().list_scenes(std::move(list));
      return true;
    }
    case msg::STATS:
      reply.status(parts_.statuses.status_message(*parts_.service.session(scene)));
      return true;
    case msg::PATH: {
      const planning::RoadmapPath path =
          parts_.service.path(scene, wire::from_message(args.path().from()), wire::from_message(args.path().to()));
      reply.body().path(to_message(path));
      reply.status(parts_.statuses.status_message(*parts_.service.session(scene)));
      return true;
    }
    case msg::SNAPSHOT: {
      const msg::SnapshotArgs& a = args.snapshot();
      const service::SnapshotSlice slice =
          parts_.service.snapshot(scene, a.version(), a.generation(), a.chunk_index(), a.poi_count());
      if (slice.chunk_index != 0) {
        reply.body().snapshot(to_message(slice, nullptr));
        return true;
      }
      const auto session = parts_.service.session(scene);
      reply.status(parts_.statuses.status_message(*session));
      // POIs only append: the scene with tasks read after the roadmap holds at least its POIs.
      reply.body().snapshot(to_message(slice, session->scene_with_tasks().get()));
      return true;
    }
    case msg::VERIFY: {
      const service::VerifyOutcome v = parts_.service.verify(scene);
      reply.message(verify_summary(v, parts_.service.stats(scene).dense_vertices));
      reply.body().verify(to_message(v));
      reply.status(parts_.statuses.status_message(*parts_.service.session(scene)));
      return true;
    }
    case msg::TOUR:
      start_tour(request, reply);
      return false;
    case msg::TASK_LIST: {
      const auto session = parts_.service.session(scene);
      const std::vector<service::InspectionTask> tasks = session->tasks();  // before the roadmap: it has their POIs
      const service::PublishedRoadmap published = session->published();
      reply.body().task_list(
          to_message(service::task_coverage(*published.roadmap, session->scene().pois().size(), tasks)));
      reply.status(parts_.statuses.status_message(*session));
      return true;
    }
    default:
      throw params::InputError(
          "request", "operation",
          fmt::format("{} is not a query (list, stats, path, snapshot, verify, tour, task list); changes go on the "
                      "change topic",
                      operation_name(args._d())));
  }
}

bool RequestRouter::answer(const msg::ChangeRequest& request, msg::Reply& reply) {
  const std::string scene = request.scene().to_string();
  if (!scene.empty()) (void)parts_.gate.wait(scene);
  const msg::ChangeArgs& args = request.args();
  switch (args._d()) {
    case msg::LOAD_SCENE: {
      const auto [s, loaded_now] = parts_.service.load(scene);
      reply.message(!loaded_now                  ? fmt::format("scene '{}' was already loaded", scene)
                    : s->recovery_note().empty() ? fmt::format("loaded scene '{}'", scene)
                                                 : s->recovery_note());
      reply.status(parts_.statuses.status_message(*s));
      return true;
    }
    case msg::UNLOAD_SCENE:
      parts_.service.unload(scene);
      reply.message(fmt::format("unloaded scene '{}' (its stored roadmap stays on disk)", scene));
      return true;
    case msg::BUILD: {
      const msg::BuildArgs& a = args.build();
      parts_.service.build(scene, wire::from_message(a, "request"));
      reply.message(fmt::format("building {} on '{}': {} samples, seed {}", a.method().to_string(), scene, a.samples(),
                                a.seed()));
      break;
    }
    case msg::EXTEND:
      parts_.service.extend(scene, args.extend().samples());
      reply.message(fmt::format("extending '{}' by {} samples", scene, args.extend().samples()));
      break;
    case msg::CANCEL: {
      const service::CancelOutcome c = parts_.service.cancel(scene);
      reply.message(fmt::format("{}; {} tour{} stopped (each replies with its best tour so far)",
                                c.build_cancelled ? "cancelling the build after the current chunk" : "no build running",
                                c.tours_stopped, c.tours_stopped == 1 ? "" : "s"));
      break;
    }
    case msg::TASK_ADD: {
      service::InspectionTask task = task_from(args.task_add(), parts_.service.session(scene)->scene());
      const std::string name = task.name;
      const std::size_t pois = task.pois.size();
      const std::size_t count = parts_.service.add_task(scene, std::move(task));
      reply.message(fmt::format("adding task '{}' ({} POIs) to the roadmap of '{}'; the scene will have {} task{}",
                                name, pois, scene, count, count == 1 ? "" : "s"));
      break;
    }
    case msg::TASK_REMOVE: {
      const std::string name = args.task_remove().name().to_string();
      const std::size_t left = parts_.service.remove_task(scene, name);
      reply.message(fmt::format("removed task '{}' from the roadmap of '{}'; {} task{} left", name, scene, left,
                                left == 1 ? "" : "s"));
      break;
    }
    case msg::DROP:
      parts_.service.drop(scene);
      parts_.out.retire_updates(scene);  // replicas drop their copy; the kept batches are released
      reply.message(fmt::format("dropped the roadmap of '{}'", scene));
      break;
    default:
      throw params::InputError(
          "request", "operation",
          fmt::format(
              "{} is not a change (load, unload, build, extend, cancel, drop, task add, task remove); queries go on "
              "the query topic",
              operation_name(args._d())));
  }
  reply.status(parts_.statuses.status_message(*parts_.service.session(scene)));
  return true;
}

void RequestRouter::start_tour(const msg::QueryRequest& request, const msg::Reply& header) {
  const msg::TourArgs& a = request.args().tour();
  service::TourRequest tour;
  if (a.targets().size() > msg::MAX_TOUR_TARGETS) {
    throw params::InputError("request", "targets",
                             fmt::format("{} given; at most {}", a.targets().size(), msg::MAX_TOUR_TARGETS));
  }
  tour.targets.assign(a.targets().begin(), a.targets().end());
  tour.budget_seconds = a.budget();
  tour.seed = a.seed();
  tour.task = a.task().to_string();
  const std::string scene = request.scene().to_string();
  const auto taken = std::chrono::steady_clock::now();
  service::TourCallbacks callbacks;
  callbacks.progress = [this, header, scene](double seconds, double cost, double bound) {
    msg::TourProgress progress;
    progress.client_id(header.client_id());
    progress.request_seq(header.request_seq());
    progress.scene(scene);
    progress.seconds(seconds);
    progress.cost(cost);
    progress.lower_bound(bound);
    parts_.out.publish_tour_progress(progress);
  };
  callbacks.done = [this, header, scene, taken](service::TourOutcome outcome) {
    msg::Reply reply = header;
    const planning::GipResult& r = outcome.result;
    reply.message(fmt::format("tour of cost {:.6g} covering {}/{} targets, {} iterations in {:.1f} s", r.tour.cost,
                              r.tour.covered.size(), r.targets.size(), r.iterations, r.seconds));
    reply.body().tour(to_message(outcome));
    try {
      reply.status(parts_.statuses.status_message(*parts_.service.session(scene)));
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
  parts_.service.start_tour(scene, std::move(tour), std::move(callbacks));
}

}  // namespace ispars::server
