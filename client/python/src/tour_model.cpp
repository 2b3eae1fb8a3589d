#include "tour_model.hpp"

#include "arrays.hpp"

namespace ispars::python {
namespace {

py::array_t<double> pairs(const std::vector<std::pair<double, double>>& trace) {
  std::vector<double> flat;
  flat.reserve(2 * trace.size());
  for (const auto& [a, b] : trace) {
    flat.push_back(a);
    flat.push_back(b);
  }
  const auto n = static_cast<py::ssize_t>(trace.size());
  return take(std::move(flat), {n, 2});
}

template <class T>
py::array_t<T> array_of(std::vector<T>&& values) {
  const auto n = static_cast<py::ssize_t>(values.size());
  return take(std::move(values), {n});
}

void add_flown(TourFields& t, py::dict& out) {
  if (!t.flown) {
    for (const char* key : {"shortcut_path", "shortcut_cost", "flown_path", "flown_sees", "flown_cost",
                            "graph_vertices", "graph_edges"}) {
      out[key] = py::none();
    }
    out["stages"] = py::list();
    return;
  }
  out["shortcut_path"] = take_points(std::move(t.shortcut_path));
  out["shortcut_cost"] = t.shortcut_cost;
  out["flown_path"] = take_points(std::move(t.flown_path));
  py::list sees;
  for (auto& seen : t.flown_sees) sees.append(array_of(std::move(seen)));
  out["flown_sees"] = sees;
  out["flown_cost"] = t.flown_cost;
  py::list stages;
  for (const TourStageFields& s : t.stages)
    stages.append(py::dict(py::arg("stage") = s.name, py::arg("cost") = s.cost, py::arg("seconds") = s.seconds));
  out["stages"] = stages;
  out["graph_vertices"] = t.graph_vertices;
  out["graph_edges"] = t.graph_edges;
}

}  // namespace

py::dict tour_dict(TourFields&& t) {
  py::dict out;
  out["cost"] = t.cost;
  out["walk"] = array_of(std::move(t.walk));
  out["waypoints"] = take_points(std::move(t.waypoints));
  out["covered"] = t.covered;
  out["target_count"] = t.target_count;
  out["lower_bound"] = t.lower_bound ? py::object(py::float_(*t.lower_bound)) : py::object(py::none());
  out["bound_complete"] = t.bound_complete;
  out["trace"] = pairs(t.trace);
  out["bound_trace"] = pairs(t.bound_trace);
  out["valid"] = t.valid;
  out["problem"] = t.problem;
  out["seconds"] = t.seconds;
  out["version"] = t.version;
  out["flown"] = t.flown;
  add_flown(t, out);
  return out;
}

}  // namespace ispars::python
