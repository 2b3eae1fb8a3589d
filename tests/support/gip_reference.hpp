#pragma once
// Small GIP instances and their exact optima, for the solver's and the bound's tests.

#include <cstdint>

#include "ispars/roadmap/inspection_graph.hpp"

namespace ispars::test {

/// A random connected geometric graph: n points in the unit cube, each joined to its `nearest`
/// nearest (0: a chain only, a path graph), plus a chain so it is connected; each vertex but
/// the root sees up to two of `pois` POIs, and every POI is seen somewhere.
InspectionGraph random_instance(std::uint64_t seed, std::size_t n, std::size_t pois, std::size_t nearest = 3);

/// The exact GIP optimum with every POI (at most 20) as a target: shortest paths between all
/// vertices, then Dijkstra over (vertex, seen set).
double exact_optimum(const InspectionGraph& g, std::size_t pois);

}  // namespace ispars::test
