// The extension module `ispars._ispars`; the package `ispars` re-exports it (ispars/__init__.py).

#include "python_module.hpp"

PYBIND11_MODULE(_ispars, m) {
  m.doc() = "ispars: Inspection-SPARS roadmaps offline (planning) and from isparsd (client).";
  ispars::python::bind_errors(m);
  ispars::python::bind_roadmap(m);
  ispars::python::bind_planning(m);
  ispars::python::bind_tour(m);
#if ISPARS_PYTHON_CLIENT
  ispars::python::route_logs();
  ispars::python::bind_client(m);
  ispars::python::bind_watch(m);
  ispars::python::bind_tasks(m);
  m.attr("HAS_CLIENT") = true;
#else
  m.attr("HAS_CLIENT") = false;  // built without DDS: no Client, no Watch
#endif
}
