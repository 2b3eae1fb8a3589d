// ispars.Roadmap: a roadmap held by Python, immutable, its arrays numpy views into it.

#include <memory>

#include "arrays.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/roadmap/record_file.hpp"
#include "ispars/roadmap/roadmap_batch.hpp"
#include "ispars/roadmap/roadmap_export.hpp"
#include "ispars/roadmap/roadmap_json.hpp"
#include "python_module.hpp"
#include "roadmap_arrays.hpp"

namespace ispars::python {
namespace {

// Writes what `text` makes to `path` atomically, without the GIL; InputError(path) on failure.
template <class F>
void save_as(const std::filesystem::path& path, F&& text) {
  try {
    py::gil_scoped_release release;  // seconds for millions of edges
    write_file_atomically(path, text());
  } catch (const std::exception& e) {
    throw params::InputError(path.string(), "path", e.what());
  }
}

const Roadmap& of(const py::object& self) { return self.cast<const Roadmap&>(); }

py::array_t<double> costs(const Roadmap& r) {
  std::vector<double> out;
  out.reserve(r.edge_count());
  const std::span<const Vec3> p = r.positions();
  for (const EdgeEnds& e : r.edge_ends()) out.push_back((p[e.u] - p[e.v]).norm());
  const auto n = static_cast<py::ssize_t>(out.size());
  return take(std::move(out), {n});
}

// Each vertex's POIs, in compressed rows: ids[offsets[v]:offsets[v + 1]] are vertex v's, ascending.
py::tuple visibility(const Roadmap& r) {
  std::vector<std::int64_t> offsets{0};
  offsets.reserve(r.vertex_count() + 1);
  std::vector<std::uint32_t> ids;
  for (VertexId v = 0; v < r.vertex_count(); ++v) {
    r.visibility_table().append_ids(v, ids);
    offsets.push_back(static_cast<std::int64_t>(ids.size()));
  }
  const auto rows = static_cast<py::ssize_t>(offsets.size());
  const auto n = static_cast<py::ssize_t>(ids.size());
  return py::make_tuple(take(std::move(offsets), {rows}), take(std::move(ids), {n}));
}

// Labels 0 .. k-1 in the order components first appear (vertex 0's is 0), as scipy's
// connected_components numbers them.
py::array_t<std::uint32_t> components(const Roadmap& r) {
  std::vector<std::uint32_t> out(r.vertex_count());
  std::vector<std::uint32_t> label_of(r.vertex_count(), kNoVertex);
  std::uint32_t labels = 0;
  for (VertexId v = 0; v < r.vertex_count(); ++v) {
    std::uint32_t& label = label_of[r.component(v)];
    if (label == kNoVertex) label = labels++;
    out[v] = label;
  }
  const auto n = static_cast<py::ssize_t>(out.size());
  return take(std::move(out), {n});
}

VertexId checked_vertex(const Roadmap& r, std::int64_t v) {
  if (v < 0 || static_cast<std::uint64_t>(v) >= r.vertex_count()) {
    throw py::index_error("vertex " + std::to_string(v) + " is not in the roadmap (" +
                          std::to_string(r.vertex_count()) + " vertices)");
  }
  return static_cast<VertexId>(v);
}

// The roadmap written to files: the roadmap file format, PLY, GraphML.
void bind_roadmap_files(py::class_<Roadmap, std::shared_ptr<Roadmap>>& roadmap) {
  roadmap
      .def(
          "save",
          [](const Roadmap& r, const std::filesystem::path& path, const std::string& scene, const py::object& root,
             const py::object& pois, const std::shared_ptr<Roadmap>& dense) {
            const Vec3 at = to_vec3(root, "root");
            const std::vector<Vec3> points = to_points(pois, "pois");
            try {
              py::gil_scoped_release release;  // seconds for millions of edges
              write_file_atomically(path, roadmap_file_json(scene, at, points, r, dense.get()));
            } catch (const std::exception& e) {
              throw params::InputError(path.string(), "path", e.what());
            }
          },
          py::arg("path"), py::arg("scene"), py::arg("root"), py::arg("pois"), py::arg("dense") = nullptr,
          "Writes the roadmap file format (ispars-lab build --out, ispars snapshot --out): the scene's name, "
          "root and POIs, this roadmap and optionally its dense pair.")
      .def(
          "save_ply",
          [](const Roadmap& r, const std::filesystem::path& path) { save_as(path, [&] { return roadmap_ply(r); }); },
          py::arg("path"),
          "Writes an ASCII PLY (MeshLab, CloudCompare, Open3D, Blender): a `vertex` element with x, y, z and the "
          "number of POIs each sees, and an `edge` element with vertex1 and vertex2 (ispars snapshot --out x.ply).")
      .def(
          "save_graphml",
          [](const Roadmap& r, const std::filesystem::path& path) {
            save_as(path, [&] { return roadmap_graphml(r); });
          },
          py::arg("path"),
          "Writes GraphML (networkx.read_graphml, Gephi, yEd, igraph): nodes with x, y, z and pois (the POI ids, "
          "space-separated), undirected edges with weight, the length (ispars snapshot --out x.graphml).");
}

}  // namespace

void bind_roadmap(py::module_& m) {
  auto roadmap =
      py::class_<Roadmap, std::shared_ptr<Roadmap>>(
          m, "Roadmap",
          "A roadmap: vertices that see POIs, and undirected edges whose cost is their length. Immutable "
          "from Python; its arrays are read-only views into it (no copy), valid as long as any of them "
          "or the roadmap lives. Pickles with its change log's order (the same digest).")
          .def_static("from_arrays", &roadmap_from_arrays, py::arg("positions"), py::arg("edges"),
                      py::arg("costs") = py::none(), py::arg("visibility") = py::none(),
                      py::arg("poi_count") = py::none(),
                      "A roadmap from anyone's graph: positions (V, 3) with vertex 0 the tour's root, edges (E, 2) of "
                      "whole vertex ids (no loops, no repeats), optional costs (E,) checked to be each edge's length "
                      "(a roadmap's costs are its segments' lengths), visibility as (offsets, ids) compressed rows "
                      "(what visibility() returns) or one POI list per vertex, and poi_count (default: the largest "
                      "id + 1). Vertices are added first, then edges, in order. Raises InputError (file "
                      "'from_arrays') naming the array and row.")
          .def(py::pickle([](const py::object& self) { return roadmap_state(self); },
                          [](const py::tuple& state) { return roadmap_from_state(state); }))
          .def_property_readonly("vertex_count", &Roadmap::vertex_count)
          .def_property_readonly("edge_count", &Roadmap::edge_count)
          .def_property_readonly("component_count", &Roadmap::component_count)
          .def_property_readonly("poi_count", &Roadmap::poi_count)
          .def_property_readonly("version", &Roadmap::version, "Vertices plus edges: the length of its change log.")
          .def_property_readonly(
              "digest", &roadmap_digest,
              "64-bit FNV-1a of the change log: equal roadmaps built in the same order have equal digests.")
          .def_property_readonly("covered_pois", &Roadmap::covered_pois, "POIs seen by some vertex.")
          .def_property_readonly(
              "covered_pois_root", [](const Roadmap& r) { return r.covered_pois_in_component_of(0); },
              "POIs seen by some vertex in the root's component (vertex 0).")
          .def_property_readonly(
              "positions", [](const py::object& self) { return points_view(of(self).positions(), self); },
              "(V, 3) float64, read-only view: vertex v's position is row v (vertex 0 is the root).")
          .def_property_readonly(
              "edges",
              [](const py::object& self) {
                const std::span<const EdgeEnds> e = of(self).edge_ends();
                return view(reinterpret_cast<const std::uint32_t*>(e.data()), e.size(), 2, self);
              },
              "(E, 2) uint32, read-only view: the two ends of each edge, in the order added.")
          .def_property_readonly("costs", &costs, "(E,) float64, new: each edge's length.")
          .def("visibility", &visibility,
               "(offsets, ids): ids[offsets[v]:offsets[v + 1]] are the POIs vertex v sees, ascending (new arrays).")
          .def(
              "pois_of",
              [](const Roadmap& r, std::int64_t v) {
                std::vector<PoiId> ids = r.visibility_table().ids(checked_vertex(r, v));
                const auto n = static_cast<py::ssize_t>(ids.size());
                return take(std::move(ids), {n});
              },
              py::arg("vertex"), "The POIs vertex `vertex` sees, ascending.")
          .def("components", &components,
               "(V,) uint32, new: each vertex's component label, 0 .. component_count - 1, numbered in the order "
               "components first appear (the root's is 0).")
          .def(
              "neighbors",
              [](const py::object& self, std::int64_t v) {
                const std::span<const VertexId> ids = of(self).neighbor_ids(checked_vertex(of(self), v));
                return view(ids.data(), ids.size(), 1, self).attr("reshape")(-1);
              },
              py::arg("vertex"), "The neighbours of `vertex`, in the order their edges were added (a read-only view).")
          .def("__repr__", [](const Roadmap& r) {
            return "<ispars.Roadmap " + std::to_string(r.vertex_count()) + " vertices, " +
                   std::to_string(r.edge_count()) + " edges>";
          });
  bind_roadmap_files(roadmap);
}

}  // namespace ispars::python
