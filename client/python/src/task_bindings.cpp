// ispars.Client's inspection tasks: add (given POIs or sampled on the surface), list, remove, as
// `ispars task` does.

#include <fmt/format.h>

#include "arrays.hpp"
#include "client_handle.hpp"
#include "ispars/params/input_error.hpp"
#include "stoppable.hpp"

namespace ispars::python {
namespace {

constexpr const char* kTask = "task";
// MAX_TASK_POIS of the IDL: the most POIs one task may give or sample.
constexpr std::int64_t kMaxTaskPois = 5000;

py::dict task_dict(const client::TaskEntry& t) {
  py::dict out;
  out["name"] = t.name;
  out["first_poi"] = t.first_poi;
  out["poi_count"] = t.poi_count;
  out["pois_covered"] = t.pois_covered;
  out["pois_covered_root"] = t.pois_covered_root;
  return out;
}

client::Reply add_task(const ClientHandle& self, const std::string& scene, const std::string& name,
                       const py::object& pois, const py::object& sample, const py::object& seed_value) {
  const std::int64_t count = to_whole_number(sample, kTask, "sample", 0, kMaxTaskPois);
  const std::uint64_t seed = to_unsigned_64(seed_value, kTask, "seed");
  if (pois.is_none() == (count == 0)) {
    throw params::InputError(kTask, "pois", "give the task's POIs or sample=N, one of the two");
  }
  if (count > 0) {
    const auto n = static_cast<std::uint32_t>(count);
    return run_detached([self, scene, name, n, seed] { return self->add_sampled_task(scene, name, n, seed); });
  }
  std::vector<Vec3> points = to_points(pois, "pois");
  if (points.empty() || static_cast<std::int64_t>(points.size()) > kMaxTaskPois) {
    throw params::InputError(kTask, "pois",
                             fmt::format("must hold 1 .. {} points, got {}", kMaxTaskPois, points.size()));
  }
  return run_detached([self, scene, name, points] { return self->add_task(scene, name, points); });
}

}  // namespace

void bind_tasks(py::module_& m) {
  auto c = py::reinterpret_borrow<py::class_<ClientHandle>>(m.attr("Client"));
  c.def(
      "add_task",
      [](const ClientHandle& self, const std::string& scene, const std::string& name, const py::object& pois,
         const py::object& sample,
         const py::object& seed) { return reply_dict(add_task(self, scene, name, pois, sample, seed)); },
      py::arg("scene"), py::arg("name"), py::arg("pois") = py::none(), py::arg("sample") = 0, py::arg("seed") = 1,
      "Adds an inspection task to the scene's built roadmap, no rebuild: `pois` (an n x 3 array, on the "
      "structure's surface) or `sample` POIs drawn on the surface from `seed` (at most 5000 either way). "
      "Queued like an extend: wait_idle() waits for it, tasks() lists it once added.");
  c.def(
      "tasks",
      [](const ClientHandle& self, const std::string& scene) {
        const std::vector<client::TaskEntry> entries = run_detached([self, scene] { return self->tasks(scene); });
        py::list out;
        for (const client::TaskEntry& t : entries) out.append(task_dict(t));
        return out;
      },
      py::arg("scene"),
      "The roadmap's tasks in the order they were added: dicts of name, first_poi, poi_count (its POIs are ids "
      "first_poi .. first_poi + poi_count - 1), pois_covered and pois_covered_root.");
  c.def(
      "remove_task",
      [](const ClientHandle& self, const std::string& scene, const std::string& name) {
        return reply_dict(run_detached([self, scene, name] { return self->remove_task(scene, name); }));
      },
      py::arg("scene"), py::arg("name"),
      "Removes the task at once: its POIs leave every target set (the roadmap keeps its vertices) and the name "
      "is free again. ClientError when no task has that name.");
}

}  // namespace ispars::python
