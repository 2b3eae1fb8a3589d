#include "roadmap_arrays.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "arrays.hpp"
#include "ispars/params/input_error.hpp"

namespace ispars::python {
namespace {

constexpr const char* kFile = "from_arrays";
constexpr std::int64_t kMaxIds = std::numeric_limits<std::uint32_t>::max() - 1;

// Each vertex's POIs, checked: compressed rows (offsets, ids) or one sequence per vertex.
std::vector<std::vector<PoiId>> read_visibility(const py::object& visibility, std::size_t vertices) {
  std::vector<std::vector<PoiId>> rows(vertices);
  if (visibility.is_none()) return rows;
  const auto to_id = [](std::int64_t id, const std::string& field) {
    if (id < 0 || id > kMaxIds) throw params::InputError(kFile, field, fmt::format("{} is not a POI id", id));
    return static_cast<PoiId>(id);
  };
  const bool compressed = py::isinstance<py::tuple>(visibility) && py::len(visibility) == 2 &&
                          py::isinstance<py::array>(visibility[py::int_(0)]);
  if (compressed) {
    const std::vector<std::int64_t> offsets = to_whole_numbers(visibility[py::int_(0)], kFile, "visibility.offsets");
    const std::vector<std::int64_t> ids = to_whole_numbers(visibility[py::int_(1)], kFile, "visibility.ids");
    if (offsets.size() != vertices + 1 || offsets.front() != 0 ||
        offsets.back() != static_cast<std::int64_t>(ids.size())) {
      throw params::InputError(
          kFile, "visibility.offsets",
          fmt::format("needs V + 1 = {} entries from 0 to len(ids) = {}", vertices + 1, ids.size()));
    }
    for (std::size_t v = 0; v < vertices; ++v) {
      if (offsets[v + 1] < offsets[v])
        throw params::InputError(kFile, "visibility.offsets", fmt::format("decreases at vertex {}", v));
      for (auto k = offsets[v]; k < offsets[v + 1]; ++k)
        rows[v].push_back(to_id(ids[static_cast<std::size_t>(k)], fmt::format("visibility.ids[{}]", k)));
    }
  } else {
    if (py::len(visibility) != vertices) {
      throw params::InputError(
          kFile, "visibility",
          fmt::format("needs one POI list per vertex ({}), got {}", vertices, py::len(visibility)));
    }
    std::size_t v = 0;
    for (const py::handle row : visibility) {
      const std::string field = fmt::format("visibility[{}]", v);
      for (const std::int64_t id : to_whole_numbers(row, kFile, field.c_str())) rows[v].push_back(to_id(id, field));
      ++v;
    }
  }
  for (auto& row : rows) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
  }
  return rows;
}

std::vector<EdgeEnds> read_edges(const py::object& edges, std::size_t vertices) {
  const py::array a = py::array::ensure(edges);
  if (!a || !((a.ndim() == 2 && a.shape(1) == 2) || a.size() == 0))
    throw params::InputError(kFile, "edges", "expected an (E, 2) array of vertex ids");
  const std::vector<std::int64_t> flat = to_whole_numbers(py::array(a.attr("reshape")(-1)), kFile, "edges");
  std::vector<EdgeEnds> out(flat.size() / 2);
  for (std::size_t k = 0; k < out.size(); ++k) {
    const std::int64_t u = flat[2 * k];
    const std::int64_t v = flat[2 * k + 1];
    if (u < 0 || v < 0 || static_cast<std::uint64_t>(std::max(u, v)) >= vertices) {
      throw params::InputError(kFile, fmt::format("edges[{}]", k),
                               fmt::format("({}, {}) names a vertex outside 0 .. {}", u, v, vertices - 1));
    }
    if (u == v) throw params::InputError(kFile, fmt::format("edges[{}]", k), fmt::format("is a loop at {}", u));
    out[k] = {static_cast<VertexId>(u), static_cast<VertexId>(v)};
  }
  return out;
}

void check_costs(const py::object& costs, std::span<const EdgeEnds> edges, std::span<const Vec3> positions) {
  if (costs.is_none()) return;
  const auto c = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(costs);
  if (!c || c.ndim() != 1 || static_cast<std::size_t>(c.shape(0)) != edges.size())
    throw params::InputError(kFile, "costs", fmt::format("expected ({},) edge costs", edges.size()));
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const double length = (positions[edges[k].u] - positions[edges[k].v]).norm();
    const double cost = c.at(static_cast<py::ssize_t>(k));
    if (!(std::abs(cost - length) <= 1e-9 * std::max(1.0, length))) {
      throw params::InputError(kFile, fmt::format("costs[{}]", k),
                               fmt::format("is {}, but the edge is {} long: a roadmap's edge costs are the lengths "
                                           "of its segments (the robot flies them)",
                                           cost, length));
    }
  }
}

}  // namespace

std::shared_ptr<Roadmap> roadmap_from_arrays(const py::object& positions, const py::object& edges,
                                             const py::object& costs, const py::object& visibility,
                                             const py::object& poi_count) {
  std::vector<Vec3> points;
  try {
    points = to_points(positions, "positions");
  } catch (const py::value_error&) {
    throw params::InputError(kFile, "positions", "expected a (V, 3) array of vertex positions, V >= 1");
  }
  if (points.empty() || points.size() > static_cast<std::size_t>(kMaxIds))
    throw params::InputError(kFile, "positions", fmt::format("needs 1 .. {} vertices (vertex 0 is the root)", kMaxIds));
  for (std::size_t v = 0; v < points.size(); ++v) {
    if (!points[v].allFinite()) throw params::InputError(kFile, fmt::format("positions[{}]", v), "is not finite");
  }
  const std::vector<EdgeEnds> ends = read_edges(edges, points.size());
  check_costs(costs, ends, points);
  std::vector<std::vector<PoiId>> rows = read_visibility(visibility, points.size());
  std::int64_t largest = -1;
  for (const auto& row : rows) {
    if (!row.empty()) largest = std::max<std::int64_t>(largest, row.back());
  }
  std::int64_t pois = largest + 1;
  if (!poi_count.is_none()) {
    pois = to_whole_number(poi_count, kFile, "poi_count", largest + 1, kMaxIds);
  }
  auto out = std::make_shared<Roadmap>(static_cast<std::size_t>(pois));
  py::gil_scoped_release release;
  for (std::size_t v = 0; v < points.size(); ++v) out->add_vertex(points[v], rows[v]);
  for (std::size_t k = 0; k < ends.size(); ++k) {
    if (!out->add_edge(ends[k].u, ends[k].v)) {
      throw params::InputError(kFile, fmt::format("edges[{}]", k),
                               fmt::format("({}, {}) repeats an earlier edge", ends[k].u, ends[k].v));
    }
  }
  return out;
}

}  // namespace ispars::python

namespace ispars::python {

py::tuple roadmap_state(const py::object& self) {
  const auto& r = self.cast<const Roadmap&>();
  std::vector<std::uint32_t> before;
  before.reserve(r.vertex_count());
  std::uint32_t edges = 0;
  r.for_each_change(0, r.version(), [&](const RoadmapChange& c) {
    if (c.kind == RoadmapChange::Kind::vertex) {
      before.push_back(edges);
    } else {
      ++edges;
    }
  });
  const std::span<const EdgeEnds> e = r.edge_ends();
  const auto n = static_cast<py::ssize_t>(before.size());
  return py::make_tuple(points_view(r.positions(), self).attr("copy")(),
                        view(reinterpret_cast<const std::uint32_t*>(e.data()), e.size(), 2, self).attr("copy")(),
                        self.attr("visibility")(), r.poi_count(), take(std::move(before), {n}));
}

std::shared_ptr<Roadmap> roadmap_from_state(const py::tuple& state) {
  if (state.size() != 5) throw params::InputError("pickle", "state", "expected the 5 parts Roadmap pickles");
  // Checked as from_arrays checks them, then rebuilt in the change log's order.
  const std::shared_ptr<Roadmap> flat = roadmap_from_arrays(state[0], state[1], py::none(), state[2], state[3]);
  const std::vector<std::int64_t> before = to_whole_numbers(state[4], "pickle", "edges_before");
  if (before.size() != flat->vertex_count())
    throw params::InputError("pickle", "edges_before", "needs one entry per vertex");
  auto out = std::make_shared<Roadmap>(flat->poi_count());
  std::size_t next_edge = 0;
  for (VertexId v = 0; v < flat->vertex_count(); ++v) {
    const auto until = static_cast<std::size_t>(std::clamp<std::int64_t>(before[v], 0, flat->edge_count()));
    for (; next_edge < until; ++next_edge) {
      const EdgeEnds e = flat->edge_ends()[next_edge];
      if (std::max(e.u, e.v) >= v) throw params::InputError("pickle", "edges_before", "places an edge before its ends");
      out->add_edge(e.u, e.v);
    }
    out->add_vertex(flat->position(v), flat->visibility_table().ids(v));
  }
  for (; next_edge < flat->edge_count(); ++next_edge)
    out->add_edge(flat->edge_ends()[next_edge].u, flat->edge_ends()[next_edge].v);
  return out;
}

}  // namespace ispars::python
