#pragma once
// The one tour model of ispars.tour (offline) and Client.tour (the daemon's): both fill a
// TourFields and return tour_dict()'s dict, so that they have the same keys of the same types.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ispars/roadmap/roadmap.hpp"
#include "python_module.hpp"

namespace ispars::python {

/// One stage of the flown tour's pipeline.
struct TourStageFields {
  std::string name;
  double cost = 0.0;
  double seconds = 0.0;
};

/// A tour's fields, whoever searched it. The flown part is set only when `flown`.
struct TourFields {
  double cost = 0.0;                ///< the walk's length on the graph
  std::vector<std::uint32_t> walk;  ///< vertex ids, closed at the root (vertex 0)
  std::vector<Vec3> waypoints;      ///< the walk's positions
  std::size_t covered = 0;          ///< targets the walk sees
  std::size_t target_count = 0;
  std::optional<double> lower_bound;  ///< proven: no walk seeing the targets is shorter
  bool bound_complete = false;
  std::vector<std::pair<double, double>> trace, bound_trace;  ///< (seconds, cost), (seconds, bound)
  bool valid = false;
  std::string problem;  ///< why not valid (empty when valid)
  double seconds = 0.0;
  std::uint64_t version = 0;  ///< the roadmap version searched
  bool flown = false;
  std::vector<Vec3> shortcut_path;
  double shortcut_cost = 0.0;
  std::vector<Vec3> flown_path;
  std::vector<std::vector<std::uint32_t>> flown_sees;
  double flown_cost = 0.0;
  std::vector<TourStageFields> stages;
  std::uint64_t graph_vertices = 0, graph_edges = 0;
};

/// The dict: the keys above (the flown ones None when not flown). docs/python.md lists them.
py::dict tour_dict(TourFields&& t);

}  // namespace ispars::python
