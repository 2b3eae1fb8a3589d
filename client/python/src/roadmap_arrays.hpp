#pragma once
// Roadmap.from_arrays: anyone's graph (an OMPL or VAMP PRM, a grid made with numpy) as an ispars
// roadmap, checked whole before a vertex is added, so that it gets ispars's tours and bounds.

#include <memory>

#include "ispars/roadmap/roadmap.hpp"
#include "python_module.hpp"

namespace ispars::python {

/// A roadmap of `positions` ((V, 3), vertex 0 the root) and `edges` ((E, 2) integer ends), each
/// vertex seeing the POIs of `visibility` ((offsets, ids) compressed rows, or one sequence per
/// vertex; None: none) among `poi_count` POIs (None: the largest id + 1). `costs` ((E,), None:
/// not checked) must be each edge's length, since a roadmap's costs are its segments' lengths.
/// Raises InputError (file "from_arrays") naming the array, the row and what is wrong.
std::shared_ptr<Roadmap> roadmap_from_arrays(const py::object& positions, const py::object& edges,
                                             const py::object& costs, const py::object& visibility,
                                             const py::object& poi_count);

}  // namespace ispars::python

namespace ispars::python {

/// A roadmap's pickle state: (positions, edges, (offsets, ids), poi_count, edges_before), where
/// edges_before[v] is the edge count when vertex v was added: the change log's interleaving, so
/// that an unpickled roadmap has the same digest.
py::tuple roadmap_state(const py::object& self);
/// The roadmap of a state from roadmap_state (checked as from_arrays checks its arrays).
std::shared_ptr<Roadmap> roadmap_from_state(const py::tuple& state);

}  // namespace ispars::python
