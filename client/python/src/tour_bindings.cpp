// ispars.tour, ispars.render and ispars.load_roadmap: tours, pictures and roadmap files offline.

#include <fmt/format.h>

#include <limits>
#include <memory>

#include "arrays.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/tour/flown_tour.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/render/scene_render.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "python_module.hpp"
#include "stoppable.hpp"

namespace ispars::python {
namespace {

constexpr const char* kTour = "tour";

py::array_t<double> pairs(const std::vector<std::pair<double, double>>& trace) {
  std::vector<double> flat;
  for (const auto& [a, b] : trace) {
    flat.push_back(a);
    flat.push_back(b);
  }
  const auto n = static_cast<py::ssize_t>(trace.size());
  return take(std::move(flat), {n, 2});
}

template <class T>
py::array_t<T> array_of(std::vector<T> values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return take(std::move(values), {n});
}

planning::GipOptions tour_options(double budget, std::int64_t iterations, std::uint64_t seed, std::int64_t threads,
                                  const py::object& targets, bool bound) {
  if (!(budget >= 0.0 && budget <= 1e6))
    throw params::InputError(kTour, "budget", fmt::format("must be 0 .. 1e6 s, got {}", budget));
  if (iterations < 0)
    throw params::InputError(kTour, "iterations", fmt::format("must be 0 or more, got {}", iterations));
  if (threads < 1 || threads > 64)
    throw params::InputError(kTour, "threads", fmt::format("must be 1 .. 64, got {}", threads));
  if (budget == 0.0 && iterations == 0)
    throw params::InputError(kTour, "budget", "give a budget or iterations (both are 0)");
  planning::GipOptions options;
  options.budget_seconds = budget;
  options.max_iterations = static_cast<std::uint64_t>(iterations);
  options.seed = seed;
  options.threads = static_cast<unsigned>(threads);
  options.lp_bound = bound;
  if (!targets.is_none()) {
    const auto ids = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(targets);
    if (!ids || ids.ndim() != 1) throw params::InputError(kTour, "targets", "expected a 1-D array of POI ids");
    std::vector<PoiId> list;
    for (py::ssize_t i = 0; i < ids.shape(0); ++i) {
      const std::int64_t id = ids.at(i);
      if (id < 0 || id > std::numeric_limits<PoiId>::max()) {
        throw params::InputError(kTour, "targets", fmt::format("{} is not a POI id", id));
      }
      list.push_back(static_cast<PoiId>(id));
    }
    options.targets = std::move(list);
  }
  return options;
}

py::dict tour_result(const planning::GipResult& r) {
  py::dict out;
  out["cost"] = r.tour.cost;
  out["walk"] = array_of(r.tour.walk);
  out["covered"] = array_of(r.tour.covered);
  out["targets"] = array_of(r.targets);
  out["lower_bound"] = r.lower_bound ? py::object(py::float_(*r.lower_bound)) : py::object(py::none());
  out["bound_complete"] = r.bound_complete;
  out["bound_note"] = r.bound_note;
  out["trace"] = pairs(r.trace);
  out["bound_trace"] = pairs(r.bound_trace);
  out["seconds"] = r.seconds;
  out["iterations"] = r.iterations;
  out["candidates"] = r.candidates;
  out["valid"] = r.validation.valid();
  out["problem"] = r.validation.problem;
  return out;
}

// The flown tour's keys beside the search's (flown_tour.hpp).
py::dict flown_result(planning::FlownTour&& t) {
  py::dict out = tour_result(t.search);
  std::vector<double> path;
  for (const Vec3& p : t.stops) path.insert(path.end(), {p.x(), p.y(), p.z()});
  out["flown_path"] = take(std::move(path), {static_cast<py::ssize_t>(t.stops.size()), 3});
  py::list sees;
  for (std::vector<PoiId>& seen : t.check.sees) sees.append(array_of(std::move(seen)));
  out["flown_sees"] = sees;
  out["flown_cost"] = t.cost;
  out["shortcut_cost"] = t.roadmap_shortcut.cost;
  py::list stages;
  for (const planning::FlownStage& s : t.stages)
    stages.append(py::dict(py::arg("stage") = s.name, py::arg("cost") = s.cost, py::arg("seconds") = s.seconds));
  out["stages"] = stages;
  out["graph_vertices"] = t.graph_vertices;
  out["graph_edges"] = t.graph_edges;
  out["valid"] = t.search.validation.valid() && t.check.valid();
  if (!t.check.valid()) out["problem"] = t.check.problem;
  return out;
}

py::dict tour(const std::shared_ptr<Roadmap>& roadmap, double budget, std::int64_t iterations, std::uint64_t seed,
              std::int64_t threads, const py::object& targets, bool bound, const std::shared_ptr<StopFlag>& stop,
              const py::object& on_improvement, const py::object& on_bound,
              const std::shared_ptr<planning::Scene>& scene, std::int64_t samples) {
  if (!roadmap) throw params::InputError(kTour, "roadmap", "a Roadmap is required");
  if (samples < 0) throw params::InputError(kTour, "samples", fmt::format("must be 0 or more, got {}", samples));
  planning::GipOptions options = tour_options(budget, iterations, seed, threads, targets, bound);
  auto halt = std::make_shared<Halt>();
  options.stop = &halt->flag();
  const Callback improved(on_improvement, halt);
  const Callback raised(on_bound, halt);
  if (improved) options.on_improvement = [improved](double t, double cost) { improved(t, cost); };
  if (raised) options.on_bound = [raised](double t, double b) { raised(t, b); };
  if (!scene) {
    const auto work = [roadmap, options] {
      return planning::solve_gip(InspectionGraph::from_roadmap(*roadmap), options);
    };
    return tour_result(run_stoppable(work, *halt, stop.get()));
  }
  planning::FlownTourOptions flown;  // the daemon's pipeline
  flown.search = options;
  flown.build_samples = static_cast<std::uint64_t>(samples);
  const auto work = [roadmap, scene, flown] {
    return planning::fly_tour(*scene, InspectionGraph::from_roadmap(*roadmap), roadmap->positions(), flown);
  };
  try {
    return flown_result(run_stoppable(work, *halt, stop.get()));
  } catch (const std::invalid_argument& e) {
    throw params::InputError(kTour, "scene", e.what());
  }
}

std::shared_ptr<Roadmap> load_roadmap(const std::string& path, const std::string& graph) {
  if (graph != "roadmap" && graph != "dense") {
    throw params::InputError(path, "graph", fmt::format("'{}' is not one of roadmap, dense", graph));
  }
  py::gil_scoped_release release;
  const RoadmapFileGraph file = read_roadmap_file_graph(path, graph);
  auto out = std::make_shared<Roadmap>(file.graph.poi_count());
  for (VertexId v = 0; v < file.graph.vertex_count(); ++v) out->add_vertex(file.positions[v], file.graph.visible(v));
  for (const RoadmapEdge& e : file.graph.edges()) out->add_edge(e.u, e.v);
  return out;
}

py::array_t<std::uint8_t> render(const std::shared_ptr<planning::Scene>& scene, const std::shared_ptr<Roadmap>& roadmap,
                                 const std::shared_ptr<Roadmap>& dense, const py::object& tour_walk, int width,
                                 int height, const std::string& path) {
  if (!scene) throw params::InputError("render", "scene", "a Scene is required");
  render::RenderRequest request;
  request.width = width;
  request.height = height;
  request.pois = scene->pois();
  if (roadmap) {
    request.roadmap = render::DrawnGraph{roadmap->positions(), roadmap->edge_ends()};
    request.poi_seen.assign(scene->pois().size(), false);
    for (VertexId v = 0; v < roadmap->vertex_count(); ++v) {
      for (const PoiId p : roadmap->visibility_table().ids(v)) {
        if (p < request.poi_seen.size()) request.poi_seen[p] = true;
      }
    }
  }
  if (dense) request.dense = render::DrawnGraph{dense->positions(), dense->edge_ends()};
  std::vector<Vec3> walk;
  if (!tour_walk.is_none()) walk = to_points(tour_walk, "tour");
  request.tour = walk;
  render::RenderResult result;
  {
    py::gil_scoped_release release;
    result = render::render_scene(scene->mesh(), request);
    if (!path.empty()) {
      try {
        render::write_png(path, result.image);
      } catch (const std::runtime_error& e) {
        throw params::InputError(path, "path", e.what());
      }
    }
  }
  const auto h = static_cast<py::ssize_t>(result.image.height);
  const auto w = static_cast<py::ssize_t>(result.image.width);
  return take(std::move(result.image.rgb), {h, w, 3});
}

}  // namespace

void bind_tour(py::module_& m) {
  m.def("tour", &tour, py::arg("roadmap"), py::arg("budget") = 10.0, py::arg("iterations") = 0, py::arg("seed") = 1,
        py::arg("threads") = 1, py::arg("targets") = py::none(), py::arg("bound") = true, py::arg("stop") = nullptr,
        py::arg("on_improvement") = py::none(), py::arg("on_bound") = py::none(), py::arg("scene") = nullptr,
        py::arg("samples") = 0,
        "An inspection tour from vertex 0 seeing every target (default: every POI seen from the root's component), "
        "searched for `budget` seconds or `iterations` iterations per thread (deterministic), without the GIL. "
        "`bound` proves a lower bound by LP beside the search. Stopped by `stop` or Ctrl-C it returns the best "
        "tour so far (Ctrl-C raises KeyboardInterrupt). A dict: cost, walk, covered, targets, lower_bound, "
        "trace, bound_trace, seconds, iterations, valid. With the roadmap's `scene` it runs the daemon's whole "
        "pipeline (the budget is then the pipeline's): the walk's shortcut, corridor densification at 4x the "
        "density of a `samples`-sample build (none when 0), viewpoint refinement and the independent check, and "
        "adds flown_path, flown_sees, flown_cost, shortcut_cost, stages, graph_vertices and graph_edges. Raises "
        "InputError (file 'tour') on bad arguments.");
  m.def("render", &render, py::arg("scene"), py::arg("roadmap") = nullptr, py::arg("dense") = nullptr,
        py::arg("tour") = py::none(), py::arg("width") = 800, py::arg("height") = 600, py::arg("path") = "",
        "A picture of the scene's mesh, its POIs (green seen by the roadmap, red not), the roadmap, its dense pair "
        "(faint) and a tour (an (n, 3) array of positions): an (height, width, 3) uint8 array, also written to "
        "`path` as PNG when given. Sizes 16 .. 8192.");
  m.def("load_roadmap", &load_roadmap, py::arg("path"), py::arg("graph") = "roadmap",
        "Reads one graph ('roadmap' or 'dense') of a roadmap file (Roadmap.save, ispars-lab build --out, ispars "
        "snapshot --out). The file keeps vertices and edges but not their interleaving, so the loaded roadmap adds "
        "every vertex before the edges: its digest is its own, not the built roadmap's.");
}

}  // namespace ispars::python
