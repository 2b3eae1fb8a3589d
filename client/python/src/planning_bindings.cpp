// ispars.Scene, ispars.Stop and ispars.Builder: the planning library offline, as ispars-lab and
// the daemon use it (the same recipe, checks and roadmap, byte for byte).

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "arrays.hpp"
#include "builder_handle.hpp"
#include "ispars/params/input_error.hpp"
#include "ispars/planning/scene/scene.hpp"
#include "ispars/planning/scene/scene_fingerprint.hpp"
#include "ispars/planning/search/path_query.hpp"
#include "python_module.hpp"
#include "stoppable.hpp"

namespace ispars::python {
namespace {

std::shared_ptr<planning::Scene> load_scene(const std::filesystem::path& path) {
  py::gil_scoped_release release;
  return std::make_shared<planning::Scene>(planning::Scene::load(path));
}

void bind_scene(py::module_& m) {
  py::class_<planning::Scene, std::shared_ptr<planning::Scene>>(
      m, "Scene", "A scene: the structure's mesh, its POIs, the sampling box and the roadmap parameters.")
      .def_static("load", &load_scene, py::arg("path"),
                  "Loads a scene YAML file (deploy/scenes/*.yaml). Raises InputError naming the file and field.")
      .def_property_readonly("name", [](const planning::Scene& s) { return s.config().name; })
      .def_property_readonly(
          "root", [](const planning::Scene& s) { return take_points({s.config().root}).attr("reshape")(3); },
          "(3,) float64: the robot's start, vertex 0 of every roadmap.")
      .def_property_readonly(
          "pois", [](const py::object& self) { return points_view(self.cast<const planning::Scene&>().pois(), self); },
          "(P, 3) float64, read-only view: POI p is row p.")
      .def_property_readonly(
          "bounds",
          [](const planning::Scene& s) {
            return take_points({s.config().bounds.min, s.config().bounds.max});
          },
          "(2, 3) float64: the sampling box's low and high corners.")
      .def_property_readonly(
          "mesh",
          [](const py::object& self) {
            const scene_files::TriangleMesh& mesh = self.cast<const planning::Scene&>().mesh();
            static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float) &&
                          sizeof(std::array<std::uint32_t, 3>) == 3 * sizeof(std::uint32_t));
            return py::make_tuple(
                view(reinterpret_cast<const float*>(mesh.vertices.data()), mesh.vertices.size(), 3, self),
                view(reinterpret_cast<const std::uint32_t*>(mesh.triangles.data()), mesh.triangles.size(), 3, self));
          },
          "(V, F): the structure's mesh as loaded and scaled, read-only views: V (n, 3) float32 corners, "
          "F (m, 3) uint32 triangles' corner ids.")
      .def_property_readonly(
          "robot_radius", [](const planning::Scene& s) { return s.config().robot_radius; },
          "The robot's radius: it is a sphere.")
      .def_property_readonly(
          "sensor_range", [](const planning::Scene& s) { return s.config().sensor_range; },
          "How far the sensor sees a POI (with a clear line of sight).")
      .def_property_readonly("dense_delta", [](const planning::Scene& s) { return s.config().dense_delta; })
      .def_property_readonly("sparse_delta", [](const planning::Scene& s) { return s.config().sparse_delta; })
      .def_property_readonly("stretch", [](const planning::Scene& s) { return s.config().stretch; })
      .def_property_readonly("fingerprint", &planning::scene_fingerprint,
                             "What the daemon checks a stored roadmap's scene against.")
      .def(
          "point_valid",
          [](const planning::Scene& s, const py::object& p) { return s.point_valid(to_vec3(p, "point")); },
          py::arg("point"), "Whether the robot may be at `point` (inside the box, clear of the mesh).")
      .def(
          "segment_valid",
          [](const planning::Scene& s, const py::object& a, const py::object& b) {
            return s.segment_valid(to_vec3(a, "a"), to_vec3(b, "b"));
          },
          py::arg("a"), py::arg("b"), "Whether the robot may fly straight from `a` to `b`.")
      .def("__repr__", [](const planning::Scene& s) {
        return fmt::format("<ispars.Scene '{}': {} POIs>", s.config().name, s.pois().size());
      });
}

void bind_stop(py::module_& m) {
  py::class_<StopFlag, std::shared_ptr<StopFlag>>(
      m, "Stop",
      "A stop for long calls (Builder.extend, Builder.verify, tour): set() from any thread ends the calls "
      "given it within half a second, keeping what they finished.")
      .def(py::init<>())
      .def("set", [](StopFlag& s) { s.set = true; })
      .def("clear", [](StopFlag& s) { s.set = false; })
      .def_property_readonly("is_set", [](const StopFlag& s) { return s.set.load(); });
}

// ispars.path: the daemon's path query (search/path_query.hpp), offline.
void bind_path(py::module_& m) {
  m.def(
      "path",
      [](const py::object& scene_value, const std::shared_ptr<Roadmap>& roadmap, const py::object& start,
         const py::object& goal, const py::object& join_radius) {
        const std::shared_ptr<planning::Scene> scene = scene_of(scene_value, "path");
        if (!roadmap) throw params::InputError("path", "roadmap", "a Roadmap is required");
        const Vec3 a = to_vec3(start, "start"), b = to_vec3(goal, "goal");
        const double radius = join_radius.is_none() ? scene->config().sparse_delta : join_radius.cast<double>();
        if (!(radius > 0.0) || !std::isfinite(radius)) {
          throw params::InputError("path", "join_radius", fmt::format("must be positive and finite, got {}", radius));
        }
        planning::RoadmapPath p;
        {
          py::gil_scoped_release release;
          p = planning::plan_path(*scene, *roadmap, a, b, radius);
        }
        py::dict out;
        out["length"] = p.length;
        out["waypoints"] = take_points(std::move(p.waypoints));
        std::vector<std::uint32_t> ids(p.vertices.begin(), p.vertices.end());
        const auto n = static_cast<py::ssize_t>(ids.size());
        out["vertices"] = take(std::move(ids), {n});
        return out;
      },
      py::arg("scene"), py::arg("roadmap"), py::arg("start"), py::arg("goal"), py::arg("join_radius") = py::none(),
      "A collision-free path from `start` to `goal` through `roadmap`, as the daemon's path query finds it: "
      "joined to vertices within `join_radius` (default: the scene's sparse_delta) by free segments. A dict of "
      "length, waypoints (n, 3) and vertices (the roadmap vertices used). Raises InputError naming a point "
      "outside the scene, in collision, or with no vertex to join, and two joins in different components.");
}

}  // namespace

std::shared_ptr<planning::Scene> scene_of(const py::object& value, const char* file) {
  if (py::isinstance<planning::Scene>(value)) return value.cast<std::shared_ptr<planning::Scene>>();
  const py::object os_path = py::module_::import("os").attr("PathLike");
  if (py::isinstance<py::str>(value) || py::isinstance(value, os_path)) {
    return load_scene(value.cast<std::filesystem::path>());
  }
  throw params::InputError(
      file, "scene",
      fmt::format("expected a Scene or a scene file's path, got {}", py::repr(value).cast<std::string>()));
}

void bind_planning(py::module_& m) {
  bind_scene(m);
  bind_stop(m);
  bind_builder(m);
  bind_path(m);
}

}  // namespace ispars::python
