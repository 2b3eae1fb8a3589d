#pragma once
// What the files of the Python module share: the pybind11 names and each file's bind function.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <memory>

namespace ispars::planning {
class Scene;
}

namespace ispars::python {

namespace py = pybind11;

/// `value` as a Scene: a Scene, or the path (str or os.PathLike) of a scene file to load.
/// Raises InputError(file, "scene") for anything else (planning_bindings.cpp).
std::shared_ptr<planning::Scene> scene_of(const py::object& value, const char* file);

/// InputError and ClientError as Python exceptions carrying their fields (errors.cpp).
void bind_errors(py::module_& m);
/// Roadmap: counts, digest, and its arrays as numpy views (roadmap_bindings.cpp).
void bind_roadmap(py::module_& m);
/// Scene, Builder, verify, Stop (planning_bindings.cpp).
void bind_planning(py::module_& m);
/// tour, render, load_roadmap (tour_bindings.cpp).
void bind_tour(py::module_& m);
/// Client and its replies (client_bindings.cpp).
void bind_client(py::module_& m);
/// The client's and Fast DDS's log lines to stderr, plain ("ispars: warning: ..."), Fast DDS's
/// coloured console output replaced; undone at interpreter exit (client_bindings.cpp).
void route_logs();
/// Client.watch's live replica (watch_bindings.cpp).
void bind_watch(py::module_& m);
/// Client's inspection tasks: add_task, tasks, remove_task (task_bindings.cpp).
void bind_tasks(py::module_& m);

}  // namespace ispars::python
