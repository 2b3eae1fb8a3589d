// ispars.tour, ispars.render and ispars.load_roadmap: tours, pictures and roadmap files offline.

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include "arrays.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/tour/flown_tour.hpp"
#include "ispars/planning/tour/gip_solver.hpp"
#include "ispars/render/scene_render.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "ispars/roadmap/roadmap_parameters.hpp"
#include "python_module.hpp"
#include "stoppable.hpp"
#include "tour_model.hpp"

namespace ispars::python {
namespace {

constexpr const char* kTour = "tour";
constexpr std::int64_t kMaxThreads = 64;
constexpr double kDefaultBudget = 10.0;

planning::GipOptions tour_options(const py::object& budget, const py::object& iterations, const py::object& seed,
                                  const py::object& threads, const py::object& targets, bool bound) {
  planning::GipOptions options;
  options.max_iterations =
      static_cast<std::uint64_t>(to_whole_number(iterations, kTour, "iterations", 0, std::int64_t{1} << 53));
  if (budget.is_none()) {
    // iterations=N alone returns when its iterations end (the LP bound stops with the search).
    options.budget_seconds = options.max_iterations > 0 ? 0.0 : kDefaultBudget;
  } else {
    const double seconds =
        py::isinstance<py::float_>(budget) || py::isinstance<py::int_>(budget) ? budget.cast<double>() : std::nan("");
    if (const std::string problem = params::problem(kTourBudget, seconds); !problem.empty())
      throw params::InputError(kTour, "budget", problem);
    options.budget_seconds = seconds;
  }
  options.seed = to_unsigned_64(seed, kTour, "seed");
  options.threads = static_cast<unsigned>(to_whole_number(threads, kTour, "threads", 1, kMaxThreads));
  options.lp_bound = bound;
  if (!targets.is_none()) {
    std::vector<PoiId> list;
    for (const std::int64_t id : to_whole_numbers(targets, kTour, "targets")) {
      if (id < 0 || id > std::numeric_limits<PoiId>::max()) {
        throw params::InputError(kTour, "targets", fmt::format("{} is not a POI id", id));
      }
      list.push_back(static_cast<PoiId>(id));
    }
    options.targets = std::move(list);
  }
  return options;
}

// The search's fields of the one tour model (tour_model.hpp).
TourFields search_fields(const planning::GipResult& r, const Roadmap& roadmap) {
  TourFields t;
  t.cost = r.tour.cost;
  t.walk.assign(r.tour.walk.begin(), r.tour.walk.end());
  for (const VertexId v : r.tour.walk) t.waypoints.push_back(roadmap.position(v));
  t.covered = r.tour.covered.size();
  t.target_count = r.targets.size();
  t.lower_bound = r.lower_bound;
  t.bound_complete = r.bound_complete;
  t.trace = r.trace;
  t.bound_trace = r.bound_trace;
  t.valid = r.validation.valid();
  t.problem = r.validation.problem;
  t.version = roadmap.version();
  return t;
}

// What only the offline search knows, beside the model's keys.
void add_search_details(const planning::GipResult& r, py::dict& out) {
  std::vector<PoiId> targets = r.targets;
  std::vector<PoiId> covered(r.tour.covered.begin(), r.tour.covered.end());
  out["targets"] = take(std::move(targets), {static_cast<py::ssize_t>(r.targets.size())});
  out["covered_ids"] = take(std::move(covered), {static_cast<py::ssize_t>(r.tour.covered.size())});
  out["bound_note"] = r.bound_note;
  out["iterations"] = r.iterations;
  out["candidates"] = r.candidates;
}

TourFields flown_fields(planning::FlownTour&& f, const Roadmap& roadmap) {
  TourFields t = search_fields(f.search, roadmap);
  t.flown = true;
  t.shortcut_path = std::move(f.roadmap_shortcut.path);
  t.shortcut_cost = f.roadmap_shortcut.cost;
  t.flown_path = std::move(f.stops);
  t.flown_sees = std::move(f.check.sees);
  t.flown_cost = f.cost;
  for (const planning::FlownStage& s : f.stages) t.stages.push_back({s.name, s.cost, s.seconds});
  t.graph_vertices = f.graph_vertices;
  t.graph_edges = f.graph_edges;
  t.valid = f.search.validation.valid() && f.check.valid();
  if (!f.check.valid()) t.problem = f.check.problem;
  return t;
}

// progress(seconds, cost, bound) from the first tour on, bound None until one is proven: the
// solver's two callbacks (from two threads) merged as the daemon merges them.
void set_progress(planning::GipOptions& options, const Callback& progress) {
  if (!progress) return;
  struct Best {
    std::mutex mutex;
    std::optional<double> cost, bound;
  };
  auto best = std::make_shared<Best>();
  options.on_improvement = [best, progress](double t, double cost) {
    std::optional<double> bound;
    {
      std::lock_guard lock(best->mutex);
      best->cost = cost;
      bound = best->bound;
    }
    progress(t, cost, bound);
  };
  options.on_bound = [best, progress](double t, double b) {
    std::optional<double> cost;
    {
      std::lock_guard lock(best->mutex);
      best->bound = b;
      cost = best->cost;
    }
    if (cost) progress(t, *cost, std::optional<double>(b));
  };
}

py::dict tour(const std::shared_ptr<Roadmap>& roadmap, const py::object& budget, const py::object& iterations,
              const py::object& seed, const py::object& threads, const py::object& targets, bool bound,
              const std::shared_ptr<StopFlag>& stop, const py::object& progress,
              const std::shared_ptr<planning::Scene>& scene, const py::object& samples) {
  if (!roadmap) throw params::InputError(kTour, "roadmap", "a Roadmap is required");
  const auto build_samples = to_whole_number(samples, kTour, "samples", 0, std::int64_t{1} << 53);
  planning::GipOptions options = tour_options(budget, iterations, seed, threads, targets, bound);
  auto halt = std::make_shared<Halt>();
  options.stop = &halt->flag();
  set_progress(options, Callback(progress, halt));
  const auto t0 = std::chrono::steady_clock::now();
  if (!scene) {
    const auto work = [roadmap, options] {
      return planning::solve_gip(InspectionGraph::from_roadmap(*roadmap), options);
    };
    const planning::GipResult r = run_stoppable(work, *halt, stop.get());
    TourFields fields = search_fields(r, *roadmap);
    fields.seconds = seconds_since(t0);
    py::dict out = tour_dict(std::move(fields));
    add_search_details(r, out);
    return out;
  }
  planning::FlownTourOptions flown;  // the daemon's pipeline
  flown.search = options;
  flown.build_samples = static_cast<std::uint64_t>(build_samples);
  const auto work = [roadmap, scene, flown] {
    return planning::fly_tour(*scene, InspectionGraph::from_roadmap(*roadmap), roadmap->positions(), flown);
  };
  try {
    planning::FlownTour f = run_stoppable(work, *halt, stop.get());
    py::dict details;  // the search's, read before flown_fields moves the tour (no copy of it)
    add_search_details(f.search, details);
    TourFields fields = flown_fields(std::move(f), *roadmap);
    fields.seconds = seconds_since(t0);
    py::dict out = tour_dict(std::move(fields));
    for (const auto& [key, value] : details) out[key] = value;
    return out;
  } catch (const std::invalid_argument& e) {
    throw params::InputError(kTour, "scene", e.what());
  }
}

std::shared_ptr<Roadmap> load_roadmap(const std::filesystem::path& path, const std::string& graph) {
  if (graph != "roadmap" && graph != "dense") {
    throw params::InputError(path.string(), "graph", fmt::format("'{}' is not one of roadmap, dense", graph));
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
                                 int height, const std::filesystem::path& path) {
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
        render::write_png(path.string(), result.image);
      } catch (const std::runtime_error& e) {
        throw params::InputError(path.string(), "path", e.what());
      }
    }
  }
  const auto h = static_cast<py::ssize_t>(result.image.height);
  const auto w = static_cast<py::ssize_t>(result.image.width);
  return take(std::move(result.image.rgb), {h, w, 3});
}

}  // namespace

void bind_tour(py::module_& m) {
  m.def("tour", &tour, py::arg("roadmap"), py::arg("budget") = py::none(), py::arg("iterations") = 0,
        py::arg("seed") = 1, py::arg("threads") = 1, py::arg("targets") = py::none(), py::arg("bound") = true,
        py::arg("stop") = nullptr, py::arg("progress") = py::none(), py::arg("scene") = nullptr, py::arg("samples") = 0,
        "An inspection tour from vertex 0 seeing every target (default: every POI seen from the root's component), "
        "without the GIL: searched for `budget` seconds (0 .. 3600, as the daemon's TOUR; default 10), or for "
        "`iterations` iterations per thread (deterministic; alone, the call returns when they end), or whichever "
        "ends first. `bound` proves a lower bound by LP beside the search. progress(seconds, cost, bound) is "
        "called from the first tour on as the tour improves or the bound rises (bound None until one is proven). "
        "Stopped by `stop` or Ctrl-C it returns the best tour so far (Ctrl-C raises KeyboardInterrupt). With the "
        "roadmap's `scene` it runs the daemon's whole pipeline (the budget is then the pipeline's): the walk's "
        "shortcut, corridor densification at 4x the density of a `samples`-sample build (none when 0), viewpoint "
        "refinement and the independent check. Returns the tour model Client.tour returns (docs/python.md, "
        "'Tours'), the flown keys None without a scene, plus targets, covered_ids, bound_note, iterations and "
        "candidates. Raises InputError (file 'tour') on bad arguments.");
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
